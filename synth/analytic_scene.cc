#include "synth/analytic_scene.h"

#include <cmath>
#include <limits>

namespace lsds::synth {

namespace {
constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d Yaw(double deg) {
  return Eigen::AngleAxisd(deg * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Slab test in the box frame; returns the entering t and the entering face's
// normal.
bool IntersectBox(const Box& box,
                  const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& direction,
                  double t_min,
                  double* t_hit,
                  Eigen::Vector3d* normal) {
  const Eigen::Matrix3d world_from_box = Yaw(box.yaw_deg);
  const Eigen::Vector3d o = world_from_box.transpose() * (origin - box.center);
  const Eigen::Vector3d d = world_from_box.transpose() * direction;
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int near_axis = -1;
  double near_sign = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double h = box.half_extents[axis];
    if (std::abs(d[axis]) < 1e-300) {
      if (std::abs(o[axis]) > h) return false;
      continue;
    }
    double t0 = (-h - o[axis]) / d[axis];
    double t1 = (h - o[axis]) / d[axis];
    double sign = -1.0;  // entering through the -h face
    if (t0 > t1) {
      std::swap(t0, t1);
      sign = 1.0;
    }
    if (t0 > t_near) {
      t_near = t0;
      near_axis = axis;
      near_sign = sign;
    }
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || t_near <= t_min || near_axis < 0) return false;  // inside or behind: no hit
  Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
  local_normal[near_axis] = near_sign;
  *t_hit = t_near;
  *normal = world_from_box * local_normal;
  return true;
}

}  // namespace

OrientedBox Box::Obb() const {
  OrientedBox obb;
  obb.center = center;
  obb.half_extents = half_extents;
  obb.world_from_box = Yaw(yaw_deg);
  return obb;
}

Hit AnalyticScene::Intersect(const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& direction,
                             double t_min,
                             int only_box) const {
  Hit best;
  if (ground && only_box < 0 && direction.z() < 0) {
    const double t = -origin.z() / direction.z();
    if (t > t_min) {
      best = {true, t, Eigen::Vector3d::UnitZ(), ground_class_id, ground_instance_id};
    }
  }
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
    if (only_box >= 0 && i != only_box) continue;
    double t;
    Eigen::Vector3d normal;
    if (IntersectBox(boxes[i], origin, direction, t_min, &t, &normal) &&
        (!best.hit || t < best.t)) {
      best = {true, t, normal, boxes[i].class_id, boxes[i].instance_id};
    }
  }
  return best;
}

}  // namespace lsds::synth
