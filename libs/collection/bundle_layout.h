// The three on-disk layouts of the pixel bundle (docs/format.md "Pixel
// bundles") and the one reader for all.
//
// full:    every sample of every pixel, channels instanceid, classid (UINT), Z,
//          NX, NY, NZ, SX, SY (FLOAT), as written up to 0.1.
// compact: only what cannot be derived. Sample positions follow the sampling
//          rule (libs/collection/sample_positions.h) and are not stored; classid
//          is a per-frame function of instanceid, stored once as a header
//          table; a pixel whose samples are all identical (same instance, the
//          same depth and normal bits) stores one sample that stands for all.
//          Lossless: the reader yields exactly the full layout's samples.
// residual: compact's derived positions and classes, and every depth and
//          normal stored as the lossless residual of a prediction from its
//          neighbours and the frame's camera (libs/collection/bundle_residual.h):
//          a fifth of compact's bytes on terrain, where no two samples of a
//          pixel have the same depth.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "libs/collection/sample_positions.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/exr_types.h"
#include "libs/geometry/camera.h"

namespace lsds {

enum class BundleLayout { kFull, kCompact, kResidual };
const char* BundleLayoutName(BundleLayout layout);  // "full" | "compact" | "residual"
bool ParseBundleLayout(const std::string& name, BundleLayout* layout);

// The channels of a full bundle, in order: what every reader yields.
const std::vector<exr::ChannelSpec>& FullBundleChannels();

// The view a residual bundle predicts depths with: the frame camera's
// intrinsics and cam_from_world rotation, and the layer's depth kind.
struct BundleView {
  PinholeCamera intrinsics;
  Eigen::Matrix3d cam_from_world_rotation = Eigen::Matrix3d::Identity();
  DepthKind depth_kind = DepthKind::kPlanar;
};

// How the bundle of one frame was sampled: what a compact or residual file
// needs to derive the sample positions, and (residual) the view.
struct BundleSampling {
  SamplerSettings sampler;
  int64_t frame = 0;
  std::optional<BundleView> view;
};

// Writes `full` (the full layout's channels, `sampler.spp` samples in every
// pixel) in `layout`. The compact encoder checks every claim it relies on:
// positions it cannot re-derive bit for bit, or class ids that are not a
// function of instance ids, are kept as channels, so the result is always
// lossless. Without `sampling` (or with other sample counts) it writes the full
// layout; `residual` without `sampling.view` writes the compact one.
void WriteBundleExr(const std::filesystem::path& path,
                    const exr::DeepImage& full,
                    BundleLayout layout,
                    const std::optional<BundleSampling>& sampling,
                    const exr::WriteOptions& options);

// Reads the named channels (all of the full layout when empty) of a bundle in
// either layout: the same samples, in the same order, whichever was written.
// Other deep files read as they are. Throws lsds::Error naming the file.
exr::DeepImage ReadBundleExr(const std::filesystem::path& path,
                             const std::vector<std::string>& channels = {},
                             const exr::ReadLimits& limits = {});

// The layout a file is stored in (its header attribute; full when absent).
BundleLayout BundleLayoutOf(const exr::ExrInfo& info);

// The channels a reader gets from a file with header `info` (for a compact or
// residual bundle: the stored ones, residuals as the values they encode, plus
// the derived ones), sorted by name as EXR lists them. Validators compare this
// against the layer table.
std::vector<exr::ChannelSpec> ReadableChannels(const exr::ExrInfo& info);

// The header attribute naming the layout ("compact" or "residual"; absent in
// full files).
inline constexpr const char* kBundleLayoutAttribute = "lsdsBundleLayout";

}  // namespace lsds
