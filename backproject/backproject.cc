#include "backproject/backproject.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>

#include "libs/util/srgb.h"

namespace lsds::pointcloud {

namespace {

// Ray directions (z == 1) through the pixel centres of every `stride`-th column
// and row, plus, for perspective depth, 1 / |ray| per sampled pixel folded into
// a per-pixel scale.
struct Rays {
  std::vector<double> x;  // per sampled column
  std::vector<double> y;  // per sampled row
};

Rays MakeRays(const PinholeCamera& camera, int width, int height, int stride) {
  Rays rays;
  for (int i = 0; i < width; i += stride) rays.x.push_back(camera.CamFromImage({i + 0.5, 0.0}).x());
  for (int j = 0; j < height; j += stride)
    rays.y.push_back(camera.CamFromImage({0.0, j + 0.5}).y());
  return rays;
}

// Point in the camera frame for depth `d` along the ray (rx, ry, 1).
inline Eigen::Vector3d CamPoint(double rx, double ry, double d, DepthKind kind) {
  const double z = kind == DepthKind::kPlanar ? d : d / std::sqrt(rx * rx + ry * ry + 1.0);
  return {rx * z, ry * z, z};
}

// 4096 steps: a 4 KiB table that stays in L1 while millions of points are
// coloured.
const std::array<uint8_t, 4097>& ToneMapTable() { return Srgb8Table<4096>(); }

}  // namespace

uint8_t ToneMap(float linear) {
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  // v > 0: truncating v + 0.5 rounds half up, as intended.
  // NOLINTNEXTLINE(bugprone-incorrect-roundings)
  return ToneMapTable()[static_cast<int>(linear * 4096.0f + 0.5f)];
}

void BackprojectFrame(const FrameLayers& layers,
                      const FramePose& pose,
                      int stride,
                      PointCloud* cloud) {
  stride = std::max(stride, 1);
  const Attributes& want = cloud->attributes;
  const Rays rays = MakeRays(pose.camera, layers.width, layers.height, stride);
  const Eigen::Matrix3d linear = pose.out_from_cam.linear();
  const Eigen::Vector3d translation = pose.out_from_cam.translation();
  const Eigen::Matrix3f normal_rotation = pose.out_from_world_normal.cast<float>();
  const bool rotate_normals = !pose.out_from_world_normal.isIdentity(0.0);
  const auto& tone = ToneMapTable();
  auto tone_map = [&tone](float v) -> uint32_t {
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return 255;
    // NOLINTNEXTLINE(bugprone-incorrect-roundings): v > 0
    return tone[static_cast<int>(v * 4096.0f + 0.5f)];
  };

  // Planar depth z along the ray (rx, ry, 1): out = z * (A (rx, ry, 1)) + b,
  // with A (rx, ry, 1) = column_term[col] + row_term[row], precomputed.
  std::vector<Eigen::Vector3d> column_term(rays.x.size());
  std::vector<Eigen::Vector3d> row_term(rays.y.size());
  for (size_t col = 0; col < rays.x.size(); ++col) {
    column_term[col] = linear.col(0) * rays.x[col];
  }
  for (size_t row = 0; row < rays.y.size(); ++row) {
    row_term[row] = linear.col(1) * rays.y[row] + linear.col(2);
  }
  const bool perspective = layers.depth_kind == DepthKind::kPerspective;

  auto sample = [&](size_t row, size_t col) {
    return row * stride * static_cast<size_t>(layers.width) + col * stride;
  };
  // Two passes over rows, both parallel: count the valid pixels of each row,
  // then fill each row's slice of the output, so the order stays row-major.
  const size_t rows = rays.y.size();
  std::vector<size_t> row_start(rows + 1, 0);
  tbb::parallel_for(size_t{0}, rows, [&](size_t row) {
    size_t count = 0;
    for (size_t col = 0; col < rays.x.size(); ++col) {
      count += IsValidDepth(layers.depth[sample(row, col)]) ? 1 : 0;
    }
    row_start[row + 1] = count;
  });
  for (size_t row = 0; row < rows; ++row) row_start[row + 1] += row_start[row];
  PointVector& out = cloud->points;
  const size_t base = out.size();
  out.resize(base + row_start[rows]);

  tbb::parallel_for(size_t{0}, rows, [&](size_t row) {
    CloudPoint* next = out.data() + base + row_start[row];
    const double ry = rays.y[row];
    for (size_t col = 0; col < rays.x.size(); ++col) {
      const size_t k = sample(row, col);
      const float d = layers.depth[k];
      if (!IsValidDepth(d)) continue;
      const double rx = rays.x[col];
      const double z = perspective ? d / std::sqrt(rx * rx + ry * ry + 1.0) : double{d};
      const Eigen::Vector3d p = z * (column_term[col] + row_term[row]) + translation;
      CloudPoint& point = *next++;
      point.x = static_cast<float>(p.x());
      point.y = static_cast<float>(p.y());
      point.z = static_cast<float>(p.z());
      point.rgb = 0;
      point.label = point.instance = 0;
      point.normal_x = point.normal_y = point.normal_z = 0;
      if (want.rgb) {
        point.rgb = (tone_map(layers.red[k]) << 16) | (tone_map(layers.green[k]) << 8) |
                    tone_map(layers.blue[k]);
      }
      if (want.labels) {
        point.label = layers.class_id[k];
        point.instance = layers.instance_id[k];
      }
      if (want.normals) {
        Eigen::Vector3f n(layers.normal_x[k], layers.normal_y[k], layers.normal_z[k]);
        if (rotate_normals) n = normal_rotation * n;
        point.normal_x = n.x();
        point.normal_y = n.y();
        point.normal_z = n.z();
      }
    }
  });
}

double ErrorStats::rms() const { return compared > 0 ? std::sqrt(sum_squared / compared) : 0.0; }

void ErrorStats::Merge(const ErrorStats& other) {
  compared += other.compared;
  max_error = std::max(max_error, other.max_error);
  sum_squared += other.sum_squared;
}

ErrorStats CompareWithWorldPosition(const FrameLayers& layers,
                                    const PinholeCamera& camera,
                                    const Eigen::Affine3d& world_from_cam,
                                    int stride,
                                    const float* world_x,
                                    const float* world_y,
                                    const float* world_z) {
  stride = std::max(stride, 1);
  const Rays rays = MakeRays(camera, layers.width, layers.height, stride);
  ErrorStats stats;
  for (size_t row = 0; row < rays.y.size(); ++row) {
    const size_t row_offset = row * stride * layers.width;
    for (size_t col = 0; col < rays.x.size(); ++col) {
      const size_t k = row_offset + col * stride;
      const float d = layers.depth[k];
      if (!IsValidDepth(d)) continue;
      const Eigen::Vector3d truth(world_x[k], world_y[k], world_z[k]);
      if (!truth.allFinite()) continue;
      const Eigen::Vector3d p =
          world_from_cam * CamPoint(rays.x[col], rays.y[row], d, layers.depth_kind);
      const double e = (p - truth).norm();
      ++stats.compared;
      stats.max_error = std::max(stats.max_error, e);
      stats.sum_squared += e * e;
    }
  }
  return stats;
}

}  // namespace lsds::pointcloud
