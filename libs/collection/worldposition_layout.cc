#include "libs/collection/worldposition_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "libs/collection/residual_layer.h"
#include "libs/exr/exr_info.h"
#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;
using exr::PixelType;

namespace {

const ResidualLayerKind& Kind() {
  static const ResidualLayerKind kind{"worldposition",
                                      {"X", "Y", "Z"},
                                      kWorldPositionLayoutAttribute,
                                      kWorldPositionDepthAttribute};
  return kind;
}

}  // namespace

const char* FlatLayoutName(FlatLayout layout) {
  return layout == FlatLayout::kResidual ? "residual" : "float";
}

bool ParseFlatLayout(const std::string& name, FlatLayout* layout) {
  if (name == "float") {
    *layout = FlatLayout::kFloat;
  } else if (name == "residual") {
    *layout = FlatLayout::kResidual;
  } else {
    return false;
  }
  return true;
}

exr::FlatImage PredictWorldPosition(const WorldPositionPrediction& input) {
  const int w = input.width, h = input.height;
  if (input.depth.size() != static_cast<size_t>(w) * h) {
    throw Error("worldposition prediction: depth has " + std::to_string(input.depth.size()) +
                " values for a " + std::to_string(w) + "x" + std::to_string(h) + " image");
  }
  exr::FlatImage out(w, h);
  float* xyz[3] = {out.AddChannel("X", PixelType::kFloat).floats.data(),
                   out.AddChannel("Y", PixelType::kFloat).floats.data(),
                   out.AddChannel("Z", PixelType::kFloat).floats.data()};
  const PinholeCamera& camera = input.camera.intrinsics;
  // The renderer's order of operations (generator/render/integrator.cc): the
  // world direction of the z == 1 ray, times the depth, from the centre.
  const Eigen::Matrix3d world_from_cam = input.camera.cam_from_world_rotation.transpose();
  const Eigen::Vector3d centre = -(world_from_cam * input.camera.cam_from_world_translation);
  const bool planar = input.depth_kind == DepthKind::kPlanar;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  tbb::parallel_for(0, h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const size_t p = static_cast<size_t>(j) * w + i;
      const float d = input.depth[p];
      if (!std::isfinite(d)) {
        for (float* c : xyz) c[p] = kInf;
        continue;
      }
      const Eigen::Vector3d ray = camera.RayThroughPixelCenter(i, j);
      const double t = planar ? double{d} : d / ray.norm();
      const Eigen::Vector3d point = centre + t * (world_from_cam * ray);
      for (int a = 0; a < 3; ++a) xyz[a][p] = static_cast<float>(point[a]);
    }
  });
  return out;
}

void WriteWorldPositionExr(const fs::path& path,
                           const exr::FlatImage& image,
                           FlatLayout layout,
                           const WorldPositionPrediction* prediction,
                           const std::string& depth_layer,
                           const exr::WriteOptions& options) {
  if (layout == FlatLayout::kFloat) {
    exr::WriteFlatExr(path, image, options);
    return;
  }
  const Location where(path.string());
  if (prediction == nullptr || depth_layer.empty()) {
    throw Error("residual worldposition layout needs the frame's depth layer", where);
  }
  if (prediction->width != image.width() || prediction->height != image.height()) {
    throw Error("residual worldposition: the depth is " + std::to_string(prediction->width) + "x" +
                    std::to_string(prediction->height) + " but the layer " +
                    std::to_string(image.width()) + "x" + std::to_string(image.height()),
                where);
  }
  WriteResidualLayer(path, image, PredictWorldPosition(*prediction), Kind(), depth_layer, options);
}

bool IsResidualWorldPosition(const exr::ExrInfo& info) { return IsResidualLayer(info, Kind()); }

std::vector<exr::ChannelSpec> ReadableWorldPositionChannels(const exr::ExrInfo& info) {
  return ReadableResidualLayerChannels(info, Kind());
}

exr::FlatImage ReadWorldPositionExr(const fs::path& path,
                                    const std::vector<std::string>& channels,
                                    const PredictionSource& prediction,
                                    const exr::ReadLimits& limits) {
  const exr::ExrInfo info = exr::ReadExrInfo(path, limits);
  if (!IsResidualWorldPosition(info)) return exr::ReadFlatExr(path, channels, limits);
  ResidualPrediction predict;
  if (prediction) {
    predict = [&](const std::string& depth_layer) {
      return PredictWorldPosition(prediction(depth_layer));
    };
  }
  return ReadResidualLayer(path, info, channels, Kind(), predict, limits);
}

WorldPositionPrediction PredictionOfFrame(const fs::path& root,
                                          const CollectionHeader& header,
                                          const Frame& frame,
                                          const std::string& depth_layer) {
  Location where((root / kCollectionFile).string());
  where.frame = frame.index;
  const LayerInfo* layer = header.FindLayer(depth_layer);
  if (layer == nullptr || layer->deep || layer->channels.empty()) {
    throw Error("a residual layer predicts from layer '" + depth_layer +
                    "', which is not a flat layer of the collection",
                where);
  }
  const auto file = frame.files.find(depth_layer);
  if (file == frame.files.end()) {
    throw Error("a residual layer predicts from layer '" + depth_layer +
                    "', but the frame has no file for it",
                where);
  }
  const fs::path path = root / file->second;
  try {
    return PredictionFromDepth(
        exr::ReadFlatExr(path, {layer->channels[0].name}), *layer, frame.camera);
  } catch (const Error& e) {
    if (!e.location().file.empty()) throw;
    throw Error(e.message(), Location(path.string()));
  }
}

WorldPositionPrediction PredictionFromDepth(const exr::FlatImage& depth,
                                            const LayerInfo& depth_layer,
                                            const CameraTruth& camera) {
  if (depth_layer.channels.empty()) {
    throw Error("depth layer '" + depth_layer.name + "' declares no channel");
  }
  const std::string& channel = depth_layer.channels[0].name;
  const exr::FlatChannel& z = depth.Get(channel);
  if (z.floats.size() != depth.pixel_count()) {
    throw Error("depth channel '" + channel + "' is not HALF or FLOAT");
  }
  WorldPositionPrediction input;
  input.depth = z.floats;
  input.width = depth.width();
  input.height = depth.height();
  input.depth_kind = depth_layer.depth_kind.value_or(DepthKind::kPlanar);
  input.camera = camera;
  return input;
}

}  // namespace lsds
