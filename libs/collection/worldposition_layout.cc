#include "libs/collection/worldposition_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "libs/collection/float_residual.h"
#include "libs/exr/exr_info.h"
#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;
using exr::PixelType;

namespace {

constexpr const char* kAxes[3] = {"X", "Y", "Z"};
constexpr const char* kResiduals[3] = {"dX", "dY", "dZ"};

// The stored channel of an axis ("X" -> "dX"), or empty for other names.
std::string ResidualOf(const std::string& axis) {
  for (int a = 0; a < 3; ++a) {
    if (axis == kAxes[a]) return kResiduals[a];
  }
  return "";
}

}  // namespace

const char* WorldPositionLayoutName(WorldPositionLayout layout) {
  return layout == WorldPositionLayout::kResidual ? "residual" : "float";
}

bool ParseWorldPositionLayout(const std::string& name, WorldPositionLayout* layout) {
  if (name == "float") {
    *layout = WorldPositionLayout::kFloat;
  } else if (name == "residual") {
    *layout = WorldPositionLayout::kResidual;
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
                           WorldPositionLayout layout,
                           const WorldPositionPrediction* prediction,
                           const std::string& depth_layer,
                           const exr::WriteOptions& options) {
  if (layout == WorldPositionLayout::kFloat) {
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
  const exr::FlatImage predicted = PredictWorldPosition(*prediction);
  exr::FlatImage out(image.width(), image.height());
  for (int a = 0; a < 3; ++a) {
    const exr::FlatChannel& truth = image.Get(kAxes[a]);
    if (truth.floats.size() != image.pixel_count() || truth.type != PixelType::kFloat) {
      throw Error(std::string("residual worldposition: channel ") + kAxes[a] + " is not FLOAT",
                  where);
    }
    const std::vector<float>& guess = predicted.Get(kAxes[a]).floats;
    std::vector<uint32_t>& residual = out.AddChannel(kResiduals[a], PixelType::kUint).uints;
    for (size_t p = 0; p < residual.size(); ++p) {
      residual[p] = FoldedDifference(FloatBits(truth.floats[p]), FloatBits(guess[p]));
    }
  }
  exr::WriteOptions write = options;
  write.attributes[kWorldPositionLayoutAttribute] = "residual";
  write.attributes[kWorldPositionDepthAttribute] = depth_layer;
  exr::WriteFlatExr(path, out, write);
}

bool IsResidualWorldPosition(const exr::ExrInfo& info) {
  const auto it = info.attributes.find(kWorldPositionLayoutAttribute);
  return it != info.attributes.end() && it->second == "residual";
}

std::vector<exr::ChannelSpec> ReadableWorldPositionChannels(const exr::ExrInfo& info) {
  if (!IsResidualWorldPosition(info)) return info.channels;
  std::vector<exr::ChannelSpec> channels;
  for (const exr::ChannelSpec& stored : info.channels) {
    std::string axis;
    for (int a = 0; a < 3; ++a) {
      if (stored.name == kResiduals[a] && stored.type == PixelType::kUint) axis = kAxes[a];
    }
    channels.push_back(axis.empty() ? stored : exr::ChannelSpec{axis, PixelType::kFloat});
  }
  std::sort(channels.begin(), channels.end(), [](const auto& a, const auto& b) {
    return a.name < b.name;
  });
  return channels;
}

exr::FlatImage ReadWorldPositionExr(const fs::path& path,
                                    const std::vector<std::string>& channels,
                                    const PredictionSource& prediction,
                                    const exr::ReadLimits& limits) {
  const exr::ExrInfo info = exr::ReadExrInfo(path, limits);
  if (!IsResidualWorldPosition(info)) return exr::ReadFlatExr(path, channels, limits);
  const Location where(path.string());
  const std::vector<std::string> wanted =
      channels.empty() ? std::vector<std::string>{"X", "Y", "Z"} : channels;
  std::vector<std::string> stored;
  for (const std::string& name : wanted) {
    const std::string residual = ResidualOf(name);
    if (residual.empty())
      throw Error("residual worldposition has no channel '" + name + "'", where);
    const exr::ChannelSpec* spec = info.Find(residual);
    if (spec == nullptr) {
      throw Error("residual worldposition has no channel '" + residual + "' (for " + name + ")",
                  where);
    }
    if (spec->type != PixelType::kUint) {
      throw Error("residual worldposition channel '" + residual + "' is " +
                      exr::PixelTypeName(spec->type) + ", expected uint",
                  where);
    }
    stored.push_back(residual);
  }
  const auto depth_attribute = info.attributes.find(kWorldPositionDepthAttribute);
  if (depth_attribute == info.attributes.end() || depth_attribute->second.empty()) {
    throw Error(std::string("residual worldposition has no header attribute '") +
                    kWorldPositionDepthAttribute + "' naming its depth layer",
                where);
  }
  if (!prediction) {
    throw Error("residual worldposition: the reader has no depth and camera to predict from",
                where);
  }
  const exr::FlatImage residuals = exr::ReadFlatExr(path, stored, limits);
  const WorldPositionPrediction input = prediction(depth_attribute->second);
  if (input.width != residuals.width() || input.height != residuals.height()) {
    throw Error("residual worldposition is " + std::to_string(residuals.width()) + "x" +
                    std::to_string(residuals.height()) + " but its depth layer '" +
                    depth_attribute->second + "' is " + std::to_string(input.width) + "x" +
                    std::to_string(input.height),
                where);
  }
  const exr::FlatImage predicted = PredictWorldPosition(input);
  exr::FlatImage out(residuals.width(), residuals.height());
  for (const std::string& name : wanted) {
    const std::vector<uint32_t>& d = residuals.Get(ResidualOf(name)).uints;
    const std::vector<float>& guess = predicted.Get(name).floats;
    std::vector<float>& value = out.AddChannel(name, PixelType::kFloat).floats;
    for (size_t p = 0; p < value.size(); ++p)
      value[p] = FloatFromBits(UnfoldedSum(FloatBits(guess[p]), d[p]));
  }
  return out;
}

WorldPositionPrediction PredictionOfFrame(const fs::path& root,
                                          const CollectionHeader& header,
                                          const Frame& frame,
                                          const std::string& depth_layer) {
  Location where((root / kCollectionFile).string());
  where.frame = frame.index;
  const LayerInfo* layer = header.FindLayer(depth_layer);
  if (layer == nullptr || layer->deep || layer->channels.empty()) {
    throw Error("residual worldposition predicts from layer '" + depth_layer +
                    "', which is not a flat layer of the collection",
                where);
  }
  const auto file = frame.files.find(depth_layer);
  if (file == frame.files.end()) {
    throw Error("residual worldposition predicts from layer '" + depth_layer +
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
