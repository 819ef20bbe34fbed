#include "libs/collection/bundle_residual.h"

#include <cmath>

#include "libs/collection/float_residual.h"

namespace lsds {

PlaneDepthPredictor::PlaneDepthPredictor(const BundleView& view)
    : camera_(view.intrinsics),
      cam_from_world_rotation_(view.cam_from_world_rotation),
      perspective_(view.depth_kind == DepthKind::kPerspective) {}

float PlaneDepthPredictor::Predict(float depth,
                                   const float normal[3],
                                   const Eigen::Vector2d& from,
                                   const Eigen::Vector2d& to) const {
  if (!std::isfinite(depth)) return depth;
  const Eigen::Vector3d normal_in_cam =
      cam_from_world_rotation_ * Eigen::Vector3d(normal[0], normal[1], normal[2]);
  // Rays with z == 1: planar depth is the ray's scale, so the plane n.p = n.(d_from r_from)
  // meets r_to at planar depth d_from (n.r_from) / (n.r_to).
  const Eigen::Vector3d ray_from = camera_.CamFromImage(from);
  const Eigen::Vector3d ray_to = camera_.CamFromImage(to);
  double scale = normal_in_cam.dot(ray_from) / normal_in_cam.dot(ray_to);
  if (perspective_) scale *= ray_to.norm() / ray_from.norm();
  const double predicted = double{depth} * scale;
  if (!std::isfinite(predicted) || predicted <= 0) return depth;
  return static_cast<float>(predicted);
}

namespace {

// The reference each sample is predicted from: the same pixel's sample 0, or
// for sample 0 the left pixel's (-1 in the first column).
int64_t ReferenceOf(const BundleRow& row, int x, int k) {
  if (k > 0) return static_cast<int64_t>(x) * row.spp;
  return x > 0 ? static_cast<int64_t>(x - 1) * row.spp : -1;
}

Eigen::Vector2d PositionOf(const BundleRow& row, int x, int64_t s) {
  return {x + double{row.sx[s]}, row.y + double{row.sy[s]}};
}

// The predicted bits of every channel of sample s (pixel x, sample k), from
// values already known: the reference's.
void Predict(const PlaneDepthPredictor& predictor,
             const BundleRow& row,
             const float* const value[4],
             int x,
             int k,
             uint32_t predicted[4]) {
  const int64_t ref = ReferenceOf(row, x, k);
  if (ref < 0) {
    for (int c = 0; c < 4; ++c) predicted[c] = 0;
    return;
  }
  for (int c = 1; c < 4; ++c) predicted[c] = value[c] ? FloatBits(value[c][ref]) : 0;
  if (value[0] != nullptr) {
    const float normal[3] = {value[1][ref], value[2][ref], value[3][ref]};
    const int ref_x = k > 0 ? x : x - 1;
    const int64_t s = static_cast<int64_t>(x) * row.spp + k;
    predicted[0] = FloatBits(predictor.Predict(
        value[0][ref], normal, PositionOf(row, ref_x, ref), PositionOf(row, x, s)));
  }
}

}  // namespace

void EncodeBundleRow(const PlaneDepthPredictor& predictor,
                     const BundleRow& row,
                     const float* const value[4],
                     uint32_t* const residual[4]) {
  uint32_t predicted[4];
  for (int x = 0; x < row.width; ++x) {
    for (int k = 0; k < row.spp; ++k) {
      Predict(predictor, row, value, x, k, predicted);
      const int64_t s = static_cast<int64_t>(x) * row.spp + k;
      for (int c = 0; c < 4; ++c) {
        residual[c][s] = FoldedDifference(FloatBits(value[c][s]), predicted[c]);
      }
    }
  }
}

void DecodeBundleRow(const PlaneDepthPredictor& predictor,
                     const BundleRow& row,
                     const uint32_t* const residual[4],
                     float* const value[4]) {
  uint32_t predicted[4];
  for (int x = 0; x < row.width; ++x) {
    for (int k = 0; k < row.spp; ++k) {
      Predict(predictor, row, value, x, k, predicted);
      const int64_t s = static_cast<int64_t>(x) * row.spp + k;
      for (int c = 0; c < 4; ++c) {
        if (value[c] != nullptr) {
          value[c][s] = FloatFromBits(UnfoldedSum(predicted[c], residual[c][s]));
        }
      }
    }
  }
}

}  // namespace lsds
