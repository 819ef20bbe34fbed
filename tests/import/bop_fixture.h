// A BlenderProc BOP dataset synthesized from an lsds analytic scene (no
// Blender needed), in the layout of BlenderProc's BOP writer (docs/import.md,
// "BlenderProc BOP"): DATASET/models/models_info.json and one scene folder
// DATASET/train_pbr/000000 with scene_camera.json (pixel-centre cam_K, mm
// poses, depth_scale), scene_gt.json, scene_gt_info.json, rgb/, depth/ (16-bit
// mm / depth_scale) and mask_visib/. Each box is its own model, obj_id b + 1.
#pragma once

#include <filesystem>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

inline constexpr double kBopDepthScale = 0.5;  // mm per depth unit

// Writes the dataset under `dataset`; returns the scene folder.
std::filesystem::path WriteBopFixture(const std::filesystem::path& dataset,
                                      const synth::Spec& spec);

}  // namespace lsds::testing
