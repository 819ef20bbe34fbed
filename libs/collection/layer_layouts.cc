#include "libs/collection/layer_layouts.h"

namespace lsds {

void LayerLayouts::UseCompact() {
  bundle = BundleLayout::kResidual;
  worldposition = FlatLayout::kResidual;
  motion = FlatLayout::kResidual;
}

void ApplyLayerLayouts(const LayerLayouts& layouts, CollectionHeader* header) {
  const bool has_depth = header->FindLayerBySemantic("depth") != nullptr;
  for (LayerInfo& layer : header->layers) {
    if (layer.deep) {
      layer.layout = layouts.bundle;
      continue;
    }
    if (!has_depth) continue;
    if (layer.semantic == "worldposition") {
      layer.flat_layout = layouts.worldposition;
    } else if (layer.semantic == "motion") {
      layer.flat_layout = layouts.motion;
    } else {
      continue;
    }
    // Small integers: piz beats zip on worldposition's (2.41 vs 2.73 MB, and faster to encode);
    // motion's are nearly all 0, where zip wins by far (0.08 vs 0.27 MB; docs/generator.md
    // "Storage"). Both lossless.
    if (layer.flat_layout == FlatLayout::kResidual && layer.semantic == "worldposition")
      layer.compression = exr::Compression::kPiz;
  }
}

}  // namespace lsds
