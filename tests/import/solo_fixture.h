// A Unity Perception SOLO dataset synthesized from an lsds analytic scene (no
// Unity needed), in the layout of com.unity.perception's SoloEndpoint
// (docs/import.md, "Unity Perception SOLO"): metadata.json,
// annotation_definitions.json with the label spec, sensor_definitions.json,
// metric_definitions.json and sequence.N/stepK.frame_data.json with one
// RGBCamera capture (Unity world: left-handed, y up; rotation [x, y, z, w];
// the projection's 3x3, column-major), stepK.camera.png, an instance
// segmentation PNG, a Depth EXR (RGBA float, planar, 0 for the sky) and
// BoundingBox3D values in the camera's frame. Frames [0, split) are
// sequence.0, the rest sequence.1. Box b is Unity instance 100 + b with the
// spec's class ids; the ground is unlabelled (black).
#pragma once

#include <filesystem>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

inline constexpr uint32_t kSoloInstanceBase = 100;

void WriteSoloFixture(const std::filesystem::path& dataset, const synth::Spec& spec, int split);

}  // namespace lsds::testing
