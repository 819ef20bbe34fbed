// A Kubric scene folder synthesized from an lsds analytic scene (no Blender
// needed), in the layout a Kubric worker writes (docs/import.md, "Kubric"):
// metadata.json (normalised K with Kubric's negated rows, camera positions and
// WXYZ quaternions of a Blender camera, instances with 8 world corners per
// frame), rgba_%05d.png (8-bit sRGB RGBA), depth_%05d.tiff (float32 ray
// distance, 1e10 for the background as Blender writes it),
// segmentation_%05d.png (palette PNG, index = instance index + 1) and
// data_ranges.json. Box b of the spec is instance b; the ground is background.
#pragma once

#include <filesystem>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

// The spec must render perspective depth (spec.depth_kind), as Kubric does.
void WriteKubricFixture(const std::filesystem::path& scene, const synth::Spec& spec);

}  // namespace lsds::testing
