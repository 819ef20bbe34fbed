// One frame rendered by Blender Cycles (render_frames.py) beside lsds's own
// render of it: Cycles' radiance becomes the rgb layer, and Cycles' depth and
// object-index passes are checked against lsds's depth and instanceid layers,
// pixel by pixel (docs/generator.md, "Blender Cycles").
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "generator/render/film.h"
#include "generator/scene_export/scene_export.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/camera.h"

namespace lsds::gen {

// How Cycles' geometry agreed with lsds's on one frame.
struct CyclesAgreement {
  int64_t frame = 0;
  int64_t pixels = 0;
  // Pixels whose instance differs (Cycles' object index mapped through the
  // export's nodes), or that one renderer sees as sky and the other not.
  int64_t id_mismatches = 0;
  // Over the pixels that agree, are not sky and whose depth is smooth in both renderers (within
  // 5 % of each neighbour's: not a silhouette, not ground at a grazing angle, not a feature
  // thinner than a pixel, where Cycles' ray, within about 0.01 px of the pixel centre, moves the
  // depth), how many and the max distance of z_cycles outside the depths lsds saw at the pixel
  // and its 4 neighbours, over z_lsds.
  int64_t depth_pixels = 0;
  double max_relative_depth_error = 0;
  double IdMismatchShare() const {
    return pixels > 0 ? static_cast<double>(id_mismatches) / static_cast<double>(pixels) : 0;
  }
};

// The file render_frames.py writes for frame `index` in `folder`: the Combined pass and, unless
// --no-truth, the Depth and Object Index passes of the same render (a multilayer EXR).
std::filesystem::path CyclesRgbPath(const std::filesystem::path& folder, int64_t index);

// Compares Cycles' passes (`cycles_exr`: Depth.Z of each pixel's first sample, which Cycles casts
// through the pixel centre, planar; IndexOB) with the film's depth (of kind `depth_kind`) and
// instanceid layers. Throws lsds::Error naming the file when it is missing, of another size, or
// lacks the passes.
CyclesAgreement CompareWithCycles(const std::filesystem::path& cycles_exr,
                                  const Film& film,
                                  const std::vector<ExportedNode>& nodes,
                                  const PinholeCamera& camera,
                                  DepthKind depth_kind,
                                  int64_t frame);

// Replaces the film's rgb by Cycles' radiance (`rgb_exr`): the same photometric units as the
// reference renderer's radiance, before the frame's exposure (MeterExposure, ApplyExposure).
void UseCyclesRgb(const std::filesystem::path& rgb_exr, Film* film);

nlohmann::json AgreementToJson(const CyclesAgreement& agreement);
CyclesAgreement AgreementFromJson(const nlohmann::json& json);

// provenance.render.cycles_agreement (docs/format.md): over every frame, the
// largest relative depth error and id mismatch share, and where they are.
nlohmann::json AgreementSummaryJson(const std::vector<CyclesAgreement>& frames);

}  // namespace lsds::gen
