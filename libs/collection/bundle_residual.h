// The residual bundle layout's prediction rule and codec (docs/format.md "Pixel
// bundles", layout `residual`). Depths and normals are stored as lossless
// residuals (libs/collection/float_residual.h) of a prediction from samples
// decoded before them, row by row, so rows decode independently:
//   - normal of sample 0 (the pixel centre): the left pixel's sample-0 normal
//     (0 in the first column);
//   - normal of sample k > 0: the same pixel's sample-0 normal;
//   - depth of sample 0: on the plane of the left pixel's sample 0 (0 in the
//     first column);
//   - depth of sample k > 0: on the plane of the same pixel's sample 0.
// "On the plane of" a sample: where the ray through the predicted sample's
// image position meets the plane through the reference sample's point with its
// normal (PlaneDepthPredictor). On the flat triangles of a terrain that is the
// renderer's own depth to a few ulps.
#pragma once

#include <Eigen/Core>

#include <cstdint>

#include "libs/collection/bundle_layout.h"

namespace lsds {

class PlaneDepthPredictor {
 public:
  explicit PlaneDepthPredictor(const BundleView& view);

  // The depth (of the view's kind) at image position `to` on the plane through
  // the point seen at image position `from` with depth `depth` and world normal
  // `normal`; `depth` itself where that is undefined (a depth that is not
  // finite, a zero normal, a plane seen edge-on or behind the camera). In
  // double, rounded to float once.
  float Predict(float depth,
                const float normal[3],
                const Eigen::Vector2d& from,
                const Eigen::Vector2d& to) const;

 private:
  PinholeCamera camera_;
  Eigen::Matrix3d cam_from_world_rotation_;
  bool perspective_ = false;
};

// One row of a bundle holding `spp` samples in every pixel: the samples of
// pixel x are [x * spp, (x + 1) * spp) of every array; `sx`/`sy` are their
// positions inside the pixel.
struct BundleRow {
  int y = 0;
  int width = 0;
  int spp = 0;
  const float* sx = nullptr;
  const float* sy = nullptr;
};

// Channel order of the arrays below: Z, NX, NY, NZ (values) and dZ, dNX, dNY,
// dNZ (residuals).
inline constexpr const char* kBundleValueChannels[4] = {"Z", "NX", "NY", "NZ"};
inline constexpr const char* kBundleResidualChannels[4] = {"dZ", "dNX", "dNY", "dNZ"};

void EncodeBundleRow(const PlaneDepthPredictor& predictor,
                     const BundleRow& row,
                     const float* const value[4],
                     uint32_t* const residual[4]);

// Decodes the channels whose `value` pointer is set (their `residual` must be
// set too); the depth needs all three normals.
void DecodeBundleRow(const PlaneDepthPredictor& predictor,
                     const BundleRow& row,
                     const uint32_t* const residual[4],
                     float* const value[4]);

}  // namespace lsds
