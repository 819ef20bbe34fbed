// The two on-disk layouts of the motion layer (docs/format.md "Motion",
// "Motion layouts") and the one reader for both.
//
// float:    channels X, Y (FLOAT): screen-normalized motion, as written up to
//           format 1.0.
// residual: channels dX, dY (UINT): the residuals (libs/collection/residual_layer.h)
//           of the motion a static world predicts: the pixel-centre point at
//           the frame's depth, seen by the previous camera of the shot, which
//           the header stores. The renderer's own value on every static
//           surface and the sky, to a few ulps; moving objects and
//           disocclusions store larger numbers. Lossless whatever the
//           prediction.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "libs/collection/model.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/exr_types.h"
#include "libs/exr/flat_image.h"

namespace lsds {

// Header attributes of a residual file: the layout ("residual"; absent in float
// files), the depth layer the prediction reads and the previous camera of the
// shot ("none" on a shot's first frame, else "width height fx fy cx cy" and the
// cam_from_world rotation row by row and translation, 18 numbers in %.17g).
inline constexpr const char* kMotionLayoutAttribute = "lsdsMotionLayout";
inline constexpr const char* kMotionDepthAttribute = "lsdsMotionDepthLayer";
inline constexpr const char* kMotionPreviousCameraAttribute = "lsdsMotionPreviousCamera";

// The one prediction rule, shared by the writer and the reader: channels X, Y
// (FLOAT), for pixel (i, j) with ray r = CamFromImage(i + 0.5, j + 0.5):
//   q = R_prev * (centre + t * R^T r) + t_prev  (a finite depth; t as in
//       PredictWorldPosition),
//   q = R_prev * R^T r                          (sky: a direction),
//   motion = 0.5 + 0.5 * ((i + 0.5, j + 0.5) - previous.ImageFromCam(q)) / (width, height),
// NaN in both where q.z <= 1e-9, where the previous image position lies outside
// [0, width) x [0, height) of the previous camera, and everywhere without a
// previous camera (a shot's first frame). In double, rounded to float once.
exr::FlatImage PredictMotion(const WorldPositionPrediction& input,
                             const std::optional<CameraTruth>& previous_camera);

// Writes `image` (channels X, Y, FLOAT) in `layout`; the residual layout
// predicts from `prediction` (the depth of layer `depth_layer` and the frame's
// camera) and `previous_camera`.
void WriteMotionExr(const std::filesystem::path& path,
                    const exr::FlatImage& image,
                    FlatLayout layout,
                    const WorldPositionPrediction* prediction,
                    const std::optional<CameraTruth>& previous_camera,
                    const std::string& depth_layer,
                    const exr::WriteOptions& options);

// Reads the named channels (X, Y when empty) of a motion file in either layout:
// plain FLOAT X, Y. Float files read as they are; a residual file needs
// `prediction` (asked once, with the depth layer its header names). Throws
// lsds::Error naming the file for a missing or malformed previous camera and
// for everything ReadResidualLayer refuses.
exr::FlatImage ReadMotionExr(const std::filesystem::path& path,
                             const std::vector<std::string>& channels,
                             const PredictionSource& prediction,
                             const exr::ReadLimits& limits = {});

bool IsResidualMotion(const exr::ExrInfo& info);

// The previous camera a residual motion file (header `info`, file `path`) was
// measured against: nullopt when its header says "none" (a shot's first
// frame). Throws lsds::Error naming the file when the attribute is missing or
// malformed.
std::optional<CameraTruth> ResidualMotionReference(const exr::ExrInfo& info,
                                                   const std::filesystem::path& path);

// The channels a reader gets from a motion file with header `info`, sorted by
// name.
std::vector<exr::ChannelSpec> ReadableMotionChannels(const exr::ExrInfo& info);

}  // namespace lsds
