// A BlenderProc BOP dataset synthesized from an lsds analytic scene (no
// Blender needed), in the layout of BlenderProc's BOP writer (docs/import.md,
// "BlenderProc BOP"): DATASET/models/models_info.json and one scene folder
// DATASET/train_pbr/000000 with scene_camera.json (pixel-centre cam_K, mm
// poses, depth_scale), scene_gt.json, scene_gt_info.json, rgb/, depth/ (16-bit
// mm / depth_scale) and mask_visib/. Each box is its own model, obj_id b + 1.
#pragma once

#include <filesystem>
#include <optional>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

inline constexpr double kBopDepthScale = 0.5;  // mm per depth unit

// Writes the dataset under `dataset`; returns the scene folder.
// How the visible masks and visib_fract are written. By default the masks
// are the scene's instance layer (a renderer's exact visibility) and
// visib_fract the scene's visibility. With `bop19_delta_m` set, as
// BlenderProc's writer does (BopWriterUtility.py _calc_gt_masks_iteration,
// _calc_gt_info_iteration through bop_toolkit visibility.estimate_visib_mask_gt,
// mode bop19): object g is visible where its own distance (the object rendered
// alone) is at most delta behind the scene's distance from the depth PNG, so
// the masks of touching objects overlap; visib_fract = visible / all pixels
// of the object alone (inside the image: the fixture's objects are not cut).
struct BopWriterRule {
  std::optional<double> bop19_delta_m;
};

std::filesystem::path WriteBopFixture(const std::filesystem::path& dataset,
                                      const synth::Spec& spec,
                                      const BopWriterRule& rule = {});

}  // namespace lsds::testing
