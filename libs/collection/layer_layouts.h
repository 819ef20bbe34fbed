// The storage layouts of the layers that have more than one (docs/format.md "Pixel bundles",
// "Worldposition layouts", "Motion layouts"), as a writer's flags choose them: the one place
// `--compact` (lsds generate, lsds import, lsds submit) maps to layouts, and the layouts to a
// collection's layer table. Every layout is lossless: readers yield the same values either way.
#pragma once

#include "libs/collection/model.h"

namespace lsds {

struct LayerLayouts {
  // The deep bundle: residual by default; compact stores depths and normals as floats; full
  // writes every channel of every sample, as format 1.0 did.
  BundleLayout bundle = BundleLayout::kResidual;
  // Worldposition and motion: float by default, plain X, Y, Z and X, Y that any EXR reader gets
  // right; residual stores UINT differences from the depth's prediction, decoded by every lsds
  // reader, for users who want the bytes.
  FlatLayout worldposition = FlatLayout::kFloat;
  FlatLayout motion = FlatLayout::kFloat;

  // `--compact`: every layer in its smallest lossless layout (the residual bundle, worldposition
  // and motion).
  void UseCompact();
};

// Sets `layouts` on the layer table of `header` (the bundle's on its deep layer, the flat ones on
// the worldposition and motion layers), with the compression that suits each. The residual
// worldposition and motion predict from the depth layer: without one they stay float.
void ApplyLayerLayouts(const LayerLayouts& layouts, CollectionHeader* header);

}  // namespace lsds
