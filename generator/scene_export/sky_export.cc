#include "generator/scene_export/sky_export.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "libs/exr/flat_image.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

// Texel sizes of the cloud shadow image (m) and its largest side.
constexpr double kFinestCloudTexelM = 1.0;
constexpr int kMaxCloudTexels = 1024;
// Just below the deck: the sun's ray from there crosses it within a
// millimetre of the point above.
constexpr double kBelowDeckM = 1e-3;

}  // namespace

Eigen::Vector3d SkyImageDirection(int width, double column, double row) {
  const int height = width / 2;
  const double longitude = 2 * M_PI * (column + 0.5) / width - M_PI;
  const double latitude = M_PI / 2 - M_PI * (row + 0.5) / height;
  return {std::cos(latitude) * std::cos(longitude),
          std::cos(latitude) * std::sin(longitude),
          std::sin(latitude)};
}

void WriteSkyImage(const Sky& sky, const fs::path& path, int width) {
  const int height = width / 2;
  exr::FlatImage image(width, height);
  exr::FlatChannel* rgb[3] = {&image.AddChannel("R", exr::PixelType::kFloat),
                              &image.AddChannel("G", exr::PixelType::kFloat),
                              &image.AddChannel("B", exr::PixelType::kFloat)};
  const Eigen::Vector3d& to_sun = sky.to_sun();
  // The disc's rim: a direction just outside it, around the sun.
  const double rim_sin = std::sqrt(1 - kSunDiscCos * kSunDiscCos);
  for (int row = 0; row < height; ++row) {
    for (int column = 0; column < width; ++column) {
      Eigen::Vector3d d = SkyImageDirection(width, column, row);
      if (d.dot(to_sun) > kSunDiscCos) {
        Eigen::Vector3d away = d - d.dot(to_sun) * to_sun;
        if (away.norm() < 1e-9) away = to_sun.unitOrthogonal();
        d = (kSunDiscCos - 1e-6) * to_sun + (rim_sin + 1e-6) * away.normalized();
        d.normalize();
      }
      const Eigen::Vector3f radiance = sky.Radiance(d);
      const size_t p = image.Index(column, row);
      for (int c = 0; c < 3; ++c) rgb[c]->floats[p] = radiance[c];
    }
  }
  exr::WriteFlatExr(path, image);
}

std::optional<CloudShadowArea> CloudShadowAreaFor(const Sky& sky,
                                                  double cloud_density,
                                                  const Eigen::Vector3d& ground_min,
                                                  const Eigen::Vector3d& ground_max) {
  const Eigen::Vector3d& s = sky.to_sun();
  if (!(cloud_density > 0) || s.z() <= 0.01) return std::nullopt;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p((corner & 1) ? ground_max.x() : ground_min.x(),
                            (corner & 2) ? ground_max.y() : ground_min.y(),
                            (corner & 4) ? ground_max.z() : ground_min.z());
    const double t = (kCloudDeckM - p.z()) / s.z();
    const Eigen::Vector2d crossing(p.x() + t * s.x(), p.y() + t * s.y());
    lo = lo.cwiseMin(crossing);
    hi = hi.cwiseMax(crossing);
  }
  CloudShadowArea area;
  const Eigen::Vector2d extent = hi - lo;
  const double texel =
      std::max(kFinestCloudTexelM, std::max(extent.x(), extent.y()) / (kMaxCloudTexels - 2));
  // One texel of margin around, so that bilinear lookups inside stay inside.
  area.width = static_cast<int>(std::ceil(extent.x() / texel)) + 2;
  area.height = static_cast<int>(std::ceil(extent.y() / texel)) + 2;
  area.min_xy = lo - Eigen::Vector2d::Constant(texel);
  area.max_xy = area.min_xy + texel * Eigen::Vector2d(area.width, area.height);
  return area;
}

nlohmann::json WriteCloudShadowImage(const Sky& sky,
                                     const CloudShadowArea& area,
                                     const fs::path& path) {
  exr::FlatImage image(area.width, area.height);
  exr::FlatChannel& share = image.AddChannel("Y", exr::PixelType::kFloat);
  const double dx = (area.max_xy.x() - area.min_xy.x()) / area.width;
  const double dy = (area.max_xy.y() - area.min_xy.y()) / area.height;
  for (int row = 0; row < area.height; ++row) {
    for (int column = 0; column < area.width; ++column) {
      const Eigen::Vector3d on_deck(area.min_xy.x() + (column + 0.5) * dx,
                                    area.max_xy.y() - (row + 0.5) * dy,
                                    kCloudDeckM - kBelowDeckM);
      share.floats[image.Index(column, row)] = static_cast<float>(sky.CloudTransmittance(on_deck));
    }
  }
  exr::WriteFlatExr(path, image);
  return {{"shadow_image", path.filename().string()},
          {"deck_height_m", kCloudDeckM},
          {"min_xy", {area.min_xy.x(), area.min_xy.y()}},
          {"max_xy", {area.max_xy.x(), area.max_xy.y()}}};
}

}  // namespace lsds::gen
