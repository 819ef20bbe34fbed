// The two on-disk layouts of the worldposition layer (docs/format.md "Layers",
// "Worldposition layouts") and the one reader for both.
//
// float:    channels X, Y, Z (FLOAT): the world position of the pixel-centre
//           sample, as written up to format 1.0.
// residual: channels dX, dY, dZ (UINT): the float bits of X, Y, Z minus the
//           float bits of their prediction, modulo 2^32. The prediction is the
//           point at the frame's depth along the pixel-centre ray of the
//           frame's camera (PredictWorldPosition), which the renderer's own
//           value almost always equals to a few ulps, so the residuals are
//           mostly 0 and compress to a fraction of the floats. Lossless by
//           construction: X = bits(prediction) + dX, whatever the prediction.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "libs/collection/model.h"
#include "libs/exr/exr_types.h"
#include "libs/exr/flat_image.h"

namespace lsds {

const char* FlatLayoutName(FlatLayout layout);  // "float" | "residual"
bool ParseFlatLayout(const std::string& name, FlatLayout* layout);

// Header attributes of a residual file: the layout ("residual"; absent in float
// files) and the name of the collection's depth layer the prediction reads.
inline constexpr const char* kWorldPositionLayoutAttribute = "lsdsWorldPositionLayout";
inline constexpr const char* kWorldPositionDepthAttribute = "lsdsWorldPositionDepthLayer";

// What the prediction of one frame reads: its depth (one float per pixel,
// row-major, of `depth_kind`) and its camera as collection.json stores it.
struct WorldPositionPrediction {
  std::vector<float> depth;
  int width = 0;
  int height = 0;
  DepthKind depth_kind = DepthKind::kPlanar;
  CameraTruth camera;
};

// The one prediction rule, shared by the writer, the reader and the importers'
// derived worldposition (importers/derived_truth.h): channels X, Y, Z
// (FLOAT) with
//   point = centre + (world_from_cam_rotation * ray) * t,
//   ray = camera.intrinsics.CamFromImage(i + 0.5, j + 0.5)   (z == 1),
//   t = depth (planar) or depth / |ray| (perspective),
//   centre = -R^T t_cam, world_from_cam_rotation = R^T
// in double, rounded to float once; +inf in all three where the depth is not
// finite (sky). R, t_cam: the camera's cam_from_world rotation and translation.
exr::FlatImage PredictWorldPosition(const WorldPositionPrediction& input);

// The prediction inputs of a frame: the depth layer named by the file and the
// frame's camera. Called by the reader only for residual files.
using PredictionSource = std::function<WorldPositionPrediction(const std::string& depth_layer)>;

// Writes `image` (channels X, Y, Z, FLOAT) in `layout`; the residual layout
// predicts from `prediction` (same size as the image), the depth of layer
// `depth_layer`.
void WriteWorldPositionExr(const std::filesystem::path& path,
                           const exr::FlatImage& image,
                           FlatLayout layout,
                           const WorldPositionPrediction* prediction,
                           const std::string& depth_layer,
                           const exr::WriteOptions& options);

// Reads the named channels (X, Y, Z when empty) of a worldposition file in
// either layout: plain FLOAT X, Y, Z, bit for bit what the float layout stores.
// Float files read as they are (any channels); a residual file needs
// `prediction` (asked once, with the depth layer its header names). Throws
// lsds::Error naming the file for missing or non-UINT residual channels, a
// missing depth attribute or a depth of another size.
exr::FlatImage ReadWorldPositionExr(const std::filesystem::path& path,
                                    const std::vector<std::string>& channels,
                                    const PredictionSource& prediction,
                                    const exr::ReadLimits& limits = {});

bool IsResidualWorldPosition(const exr::ExrInfo& info);

// The channels a reader gets from a residual file with header `info` (X, Y, Z
// FLOAT for each stored dX, dY, dZ UINT; other channels as stored), sorted by
// name; other files: their channels.
std::vector<exr::ChannelSpec> ReadableWorldPositionChannels(const exr::ExrInfo& info);

// The prediction inputs from a decoded image of depth layer `depth_layer` (its
// first channel, HALF or FLOAT, and its depth_kind) and the frame's camera.
// Throws lsds::Error for a layer without channels or a channel of another type.
WorldPositionPrediction PredictionFromDepth(const exr::FlatImage& depth,
                                            const LayerInfo& depth_layer,
                                            const CameraTruth& camera);

// The prediction inputs of `frame` from a collection folder: the frame's file
// of layer `depth_layer` (its first channel), that layer's depth_kind and the
// frame's camera. Throws lsds::Error naming collection.json when the header has
// no such flat layer or the frame no such file.
WorldPositionPrediction PredictionOfFrame(const std::filesystem::path& root,
                                          const CollectionHeader& header,
                                          const Frame& frame,
                                          const std::string& depth_layer);

}  // namespace lsds
