// A smooth field evaluated once per pixel. The procedural albedo and the cloud
// shadow change by under an 8-bit step within their reuse distances
// (AlbedoReuseDistance, Sky::CloudReuseDistance), and a pixel's footprint is
// usually smaller than that, so a pixel's samples that hit the same surface
// near the point the field was evaluated at take that value instead of
// evaluating the noise again (docs/generator.md, "Smooth fields once per
// pixel"). Samples are visited in order, the centre sample first, so the value
// is the centre sample's wherever it applies: the single-value truth layers
// (shadow) keep their exact per-sample values.
#pragma once

#include <Eigen/Core>

namespace lsds::gen {

// A field's value at a point, and how far (m) around the point it holds.
template <typename Value>
struct FieldValue {
  Value value;
  double reuse_distance = 0;
};

template <typename Value>
class PixelField {
 public:
  // `unset` is never returned; it only keeps the storage initialized.
  explicit PixelField(const Value& unset) : kept_{unset, 0} {}

  // At each pixel's first sample: the pixel has no value yet.
  void Reset() { valid_ = false; }

  // Whether the value kept for this pixel holds at `point` on surface `geom`:
  // it was evaluated on the same surface within its reuse distance.
  bool Holds(unsigned geom, const Eigen::Vector3d& point) const {
    return valid_ && geom == geom_ &&
           (point - point_).squaredNorm() <= kept_.reuse_distance * kept_.reuse_distance;
  }

  // The field at `point` on surface `geom`: the value kept for this pixel
  // where it holds, else `evaluate()` (a FieldValue<Value>), which is then
  // kept.
  template <typename Evaluate>
  Value At(unsigned geom, const Eigen::Vector3d& point, Evaluate&& evaluate) {
    if (Holds(geom, point)) return kept_.value;
    kept_ = evaluate();
    geom_ = geom;
    point_ = point;
    valid_ = true;
    return kept_.value;
  }

 private:
  bool valid_ = false;
  unsigned geom_ = 0;
  Eigen::Vector3d point_ = Eigen::Vector3d::Zero();
  FieldValue<Value> kept_;
};

// A value that is exactly the same, bit for bit, everywhere within a ball
// around the point it was evaluated at (the cloud shadow where the deck is
// clear or full: Sky::CloudTransmittance's exact distance). Unlike a
// PixelField it may be kept across pixels and blocks: whichever point it came
// from, a fresh evaluation would give the same bits, so the images do not
// depend on the order pixels are visited in.
template <typename Value>
class ExactBall {
 public:
  // The kept value if `point` is inside the ball, and how far around `point`
  // it still holds.
  bool Find(const Eigen::Vector3d& point, Value* value, double* remaining) const {
    if (!(radius_ > 0)) return false;
    const double distance = (point - centre_).norm();
    if (distance > radius_) return false;
    *value = value_;
    *remaining = radius_ - distance;
    return true;
  }

  // Keeps `value` for the ball of `radius` around `point`; a radius of 0
  // keeps the ball it had.
  void Keep(const Eigen::Vector3d& point, const Value& value, double radius) {
    if (!(radius > 0)) return;
    centre_ = point;
    value_ = value;
    radius_ = radius;
  }

 private:
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  Value value_{};
  double radius_ = 0;
};

}  // namespace lsds::gen
