#include "libs/collection/motion_layout.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <tbb/parallel_for.h>

#include "libs/collection/residual_layer.h"
#include "libs/exr/exr_info.h"
#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;
using exr::PixelType;

namespace {

const ResidualLayerKind& Kind() {
  static const ResidualLayerKind kind{
      "motion", {"X", "Y"}, kMotionLayoutAttribute, kMotionDepthAttribute};
  return kind;
}

std::string FormatCamera(const std::optional<CameraTruth>& camera) {
  if (!camera) return "none";
  const PinholeCamera& k = camera->intrinsics;
  std::string text = std::to_string(k.width) + ' ' + std::to_string(k.height);
  auto add = [&](double v) {
    char number[40];
    std::snprintf(number, sizeof number, " %.17g", v);
    text += number;
  };
  for (double v : {k.fx, k.fy, k.cx, k.cy}) add(v);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) add(camera->cam_from_world_rotation(r, c));
  }
  for (int a = 0; a < 3; ++a) add(camera->cam_from_world_translation[a]);
  return text;
}

}  // namespace

exr::FlatImage PredictMotion(const WorldPositionPrediction& input,
                             const std::optional<CameraTruth>& previous_camera) {
  const int w = input.width, h = input.height;
  if (input.depth.size() != static_cast<size_t>(w) * h) {
    throw Error("motion prediction: depth has " + std::to_string(input.depth.size()) +
                " values for a " + std::to_string(w) + "x" + std::to_string(h) + " image");
  }
  exr::FlatImage out(w, h);
  float* mx = out.AddChannel("X", PixelType::kFloat).floats.data();
  float* my = out.AddChannel("Y", PixelType::kFloat).floats.data();
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  if (!previous_camera) {
    std::fill(mx, mx + out.pixel_count(), kNaN);
    std::fill(my, my + out.pixel_count(), kNaN);
    return out;
  }
  const PinholeCamera& camera = input.camera.intrinsics;
  const PinholeCamera& before = previous_camera->intrinsics;
  const Eigen::Matrix3d world_from_cam = input.camera.cam_from_world_rotation.transpose();
  const Eigen::Vector3d centre = -(world_from_cam * input.camera.cam_from_world_translation);
  const Eigen::Matrix3d& previous_rotation = previous_camera->cam_from_world_rotation;
  const Eigen::Vector3d& previous_translation = previous_camera->cam_from_world_translation;
  const bool planar = input.depth_kind == DepthKind::kPlanar;
  tbb::parallel_for(0, h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const size_t p = static_cast<size_t>(j) * w + i;
      const float d = input.depth[p];
      const Eigen::Vector3d ray = camera.RayThroughPixelCenter(i, j);
      const Eigen::Vector3d direction = world_from_cam * ray;
      Eigen::Vector3d in_previous;
      if (std::isfinite(d)) {
        const double t = planar ? double{d} : d / ray.norm();
        in_previous = previous_rotation * (centre + t * direction) + previous_translation;
      } else {
        in_previous = previous_rotation * direction;
      }
      mx[p] = my[p] = kNaN;
      if (!(in_previous.z() > 1e-9)) continue;
      const Eigen::Vector2d seen = before.ImageFromCam(in_previous);
      if (!(seen.x() >= 0 && seen.x() < before.width && seen.y() >= 0 && seen.y() < before.height))
        continue;
      mx[p] = static_cast<float>(0.5 + 0.5 * (i + 0.5 - seen.x()) / camera.width);
      my[p] = static_cast<float>(0.5 + 0.5 * (j + 0.5 - seen.y()) / camera.height);
    }
  });
  return out;
}

void WriteMotionExr(const fs::path& path,
                    const exr::FlatImage& image,
                    FlatLayout layout,
                    const WorldPositionPrediction* prediction,
                    const std::optional<CameraTruth>& previous_camera,
                    const std::string& depth_layer,
                    const exr::WriteOptions& options) {
  if (layout == FlatLayout::kFloat) {
    exr::WriteFlatExr(path, image, options);
    return;
  }
  if (prediction == nullptr || depth_layer.empty()) {
    throw Error("residual motion layout needs the frame's depth layer", Location(path.string()));
  }
  exr::WriteOptions write = options;
  write.attributes[kMotionPreviousCameraAttribute] = FormatCamera(previous_camera);
  WriteResidualLayer(
      path, image, PredictMotion(*prediction, previous_camera), Kind(), depth_layer, write);
}

bool IsResidualMotion(const exr::ExrInfo& info) { return IsResidualLayer(info, Kind()); }

std::optional<CameraTruth> ResidualMotionReference(const exr::ExrInfo& info, const fs::path& path) {
  const auto it = info.attributes.find(kMotionPreviousCameraAttribute);
  if (it == info.attributes.end()) {
    throw Error(std::string("residual motion has no header attribute '") +
                    kMotionPreviousCameraAttribute + "'",
                Location(path.string()));
  }
  if (it->second == "none") return std::nullopt;
  std::istringstream in(it->second);
  std::vector<double> v;
  double x = 0;
  while (in >> x) v.push_back(x);
  if (!in.eof() || v.size() != 18 || !(v[0] >= 1 && v[1] >= 1 && v[0] <= 1e6 && v[1] <= 1e6)) {
    throw Error(std::string("residual motion header attribute '") + kMotionPreviousCameraAttribute +
                    "' = '" + it->second +
                    "' is not 'none' or 18 numbers (width height fx fy cx cy, rotation, "
                    "translation)",
                Location(path.string()));
  }
  CameraTruth camera;
  camera.intrinsics.width = static_cast<int>(v[0]);
  camera.intrinsics.height = static_cast<int>(v[1]);
  camera.intrinsics.fx = v[2];
  camera.intrinsics.fy = v[3];
  camera.intrinsics.cx = v[4];
  camera.intrinsics.cy = v[5];
  for (int i = 0; i < 9; ++i) camera.cam_from_world_rotation(i / 3, i % 3) = v[6 + i];
  for (int a = 0; a < 3; ++a) camera.cam_from_world_translation[a] = v[15 + a];
  return camera;
}

std::vector<exr::ChannelSpec> ReadableMotionChannels(const exr::ExrInfo& info) {
  return ReadableResidualLayerChannels(info, Kind());
}

exr::FlatImage ReadMotionExr(const fs::path& path,
                             const std::vector<std::string>& channels,
                             const PredictionSource& prediction,
                             const exr::ReadLimits& limits) {
  const exr::ExrInfo info = exr::ReadExrInfo(path, limits);
  if (!IsResidualMotion(info)) return exr::ReadFlatExr(path, channels, limits);
  const std::optional<CameraTruth> previous_camera = ResidualMotionReference(info, path);
  ResidualPrediction predict;
  if (prediction) {
    predict = [&](const std::string& depth_layer) {
      return PredictMotion(prediction(depth_layer), previous_camera);
    };
  }
  return ReadResidualLayer(path, info, channels, Kind(), predict, limits);
}

}  // namespace lsds
