#include "generator/plan/relations.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

namespace lsds {

bool RelationHolds(const Relation& relation, const Eigen::Vector3d& point_in_world) {
  const Eigen::Vector2d offset = point_in_world.head<2>() - relation.ref_xy;
  if (offset.norm() > relation.distance) return false;
  const double ahead = offset.dot(relation.ref_heading);
  switch (relation.kind) {
    case Relation::Kind::kBehind:
      return ahead < 0;
    case Relation::Kind::kInFront:
      return ahead > 0;
    default:
      return true;
  }
}

void RelationBounds(const Relation& relation, Eigen::Vector2d* lo, Eigen::Vector2d* hi) {
  const double inf = std::numeric_limits<double>::infinity();
  *lo = Eigen::Vector2d::Constant(-inf);
  *hi = Eigen::Vector2d::Constant(inf);
  if (!std::isfinite(relation.distance)) return;
  *lo = relation.ref_xy.array() - relation.distance;
  *hi = relation.ref_xy.array() + relation.distance;
}

Eigen::Vector2d HeadingOf(const Eigen::Matrix3d& world_from_object) {
  const Eigen::Vector2d forward = world_from_object.col(0).head<2>();
  const double n = forward.norm();
  return n > 1e-12 ? Eigen::Vector2d(forward / n) : Eigen::Vector2d::UnitX();
}

Eigen::Matrix3d FacingRotation(const Eigen::Matrix3d& world_from_object,
                               const Eigen::Vector3d& from,
                               const Eigen::Vector3d& toward) {
  const Eigen::Vector2d d = (toward - from).head<2>();
  if (d.norm() <= 1e-12) return world_from_object;
  const Eigen::Vector2d h = HeadingOf(world_from_object);
  const double turn = std::atan2(d.y(), d.x()) - std::atan2(h.y(), h.x());
  return Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix() * world_from_object;
}

double HorizontalRadius(const Eigen::Matrix3d& world_from_object, const Eigen::Vector3d& extent) {
  double radius = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner_in_object((k & 1 ? 0.5 : -0.5) * extent.x(),
                                           (k & 2 ? 0.5 : -0.5) * extent.y(),
                                           (k & 4 ? 0.5 : -0.5) * extent.z());
    radius = std::max(radius, (world_from_object * corner_in_object).head<2>().norm());
  }
  return radius;
}

bool SegmentCrossesBox(const OrientedBox& box, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  // Slab test in the box's frame over the segment's parameter t in [0, 1].
  const Eigen::Vector3d a_in_box = box.world_from_box.transpose() * (a - box.center);
  const Eigen::Vector3d d_in_box = box.world_from_box.transpose() * (b - a);
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    const double h = box.half_extents[i];
    if (std::abs(d_in_box[i]) < 1e-15) {
      if (std::abs(a_in_box[i]) >= h) return false;
      continue;
    }
    double ta = (-h - a_in_box[i]) / d_in_box[i], tb = (h - a_in_box[i]) / d_in_box[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 >= t1) return false;
  }
  return true;
}

}  // namespace lsds
