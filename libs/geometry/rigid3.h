// A rigid transform, named by its frames as in COLMAP: `cam_from_world *
// point_in_world` is the point in the camera frame.
#pragma once

#include <Eigen/Geometry>

namespace lsds {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& r, const Eigen::Vector3d& t) : rotation(r), translation(t) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return rotation * point + translation;
  }
  Rigid3d operator*(const Rigid3d& other) const {  // (a_from_b * b_from_c) = a_from_c
    return Rigid3d(rotation * other.rotation, rotation * other.translation + translation);
  }
  Rigid3d Inverse() const {
    const Eigen::Quaterniond inverse = rotation.conjugate();
    return Rigid3d(inverse, -(inverse * translation));
  }
  Eigen::Matrix4d ToMatrix() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = rotation.toRotationMatrix();
    m.topRightCorner<3, 1>() = translation;
    return m;
  }
};

// The camera centre in world coordinates for a `cam_from_world` pose.
inline Eigen::Vector3d CameraCenterInWorld(const Rigid3d& cam_from_world) {
  return cam_from_world.Inverse().translation;
}

// A `cam_from_world` pose for a camera at `eye_in_world` looking at
// `target_in_world`, with the image's "up" (-y in the OpenCV camera frame) as
// close as possible to `up_in_world`.
inline Rigid3d LookAt(const Eigen::Vector3d& eye_in_world,
                      const Eigen::Vector3d& target_in_world,
                      const Eigen::Vector3d& up_in_world = Eigen::Vector3d::UnitZ()) {
  const Eigen::Vector3d z = (target_in_world - eye_in_world).normalized();
  Eigen::Vector3d x = z.cross(up_in_world);
  if (x.squaredNorm() < 1e-12) x = z.cross(Eigen::Vector3d::UnitY());  // looking along up
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d world_from_cam;
  world_from_cam << x, y, z;
  const Eigen::Quaterniond world_from_cam_rotation(world_from_cam);
  return Rigid3d(world_from_cam_rotation, eye_in_world).Inverse();
}

}  // namespace lsds
