#include "importers/unreal_frame.h"

#include <cmath>

#include <Eigen/Geometry>

#include "libs/geometry/world_frame.h"

namespace lsds::import {

namespace {
constexpr double kPi = 3.14159265358979323846;
double Rad(double deg) { return deg * kPi / 180.0; }
double Deg(double rad) { return rad * 180.0 / kPi; }

const WorldFrame& Unreal() {
  static const WorldFrame frame = WorldFrame::Make("unreal", "cm");
  return frame;
}
// Directions (no scale) between the frames.
Eigen::Vector3d EnuDirection(const Eigen::Vector3d& d) { return Unreal().enu_from_frame * d; }
Eigen::Vector3d UnrealDirection(const Eigen::Vector3d& d) {
  return Unreal().enu_from_frame.transpose() * d;
}
}  // namespace

Eigen::Matrix3d UnrealAxes(const UnrealRotator& r) {
  const double sp = std::sin(Rad(r.pitch)), cp = std::cos(Rad(r.pitch));
  const double sy = std::sin(Rad(r.yaw)), cy = std::cos(Rad(r.yaw));
  const double sr = std::sin(Rad(r.roll)), cr = std::cos(Rad(r.roll));
  Eigen::Matrix3d m;
  m << cp * cy, cp * sy, sp,                                     //
      sr * sp * cy - cr * sy, sr * sp * sy + cr * cy, -sr * cp,  //
      -(cr * sp * cy + sr * sy), cy * sr - cr * sp * sy, cr * cp;
  return m;
}

UnrealRotator UnrealRotatorFromAxes(const Eigen::Matrix3d& axes) {
  const Eigen::Vector3d x = axes.row(0), y = axes.row(1), z = axes.row(2);
  UnrealRotator r;
  r.pitch = Deg(std::atan2(x.z(), std::hypot(x.x(), x.y())));
  r.yaw = Deg(std::atan2(x.y(), x.x()));
  const Eigen::Vector3d unrolled_y = UnrealAxes({r.pitch, r.yaw, 0}).row(1);
  r.roll = Deg(std::atan2(z.dot(unrolled_y), y.dot(unrolled_y)));
  return r;
}

Eigen::Vector3d EnuMetresFromUnreal(const Eigen::Vector3d& p) {
  return Unreal().EnuMetresFromWorld(p);
}
Eigen::Vector3d UnrealFromEnuMetres(const Eigen::Vector3d& p) {
  return Unreal().WorldFromEnuMetres(p);
}

Rigid3d CamFromEnuOfUnrealCamera(const Eigen::Vector3d& location_cm,
                                 const UnrealRotator& rotation) {
  const Eigen::Matrix3d axes = UnrealAxes(rotation);
  const Eigen::Vector3d forward = EnuDirection(axes.row(0).transpose());
  const Eigen::Vector3d right = EnuDirection(axes.row(1).transpose());
  const Eigen::Vector3d up = EnuDirection(axes.row(2).transpose());
  // OpenCV camera: x right, y down, z forward; rows are those axes in ENU.
  Eigen::Matrix3d cam_from_enu;
  cam_from_enu.row(0) = right;
  cam_from_enu.row(1) = -up;
  cam_from_enu.row(2) = forward;
  const Eigen::Quaterniond rotation_q(cam_from_enu);
  const Eigen::Vector3d centre = EnuMetresFromUnreal(location_cm);
  return Rigid3d(rotation_q.normalized(), -(rotation_q.normalized() * centre));
}

void UnrealCameraOfCamFromEnu(const Rigid3d& cam_from_enu,
                              Eigen::Vector3d* location_cm,
                              UnrealRotator* rotation) {
  const Eigen::Matrix3d r = cam_from_enu.rotation.toRotationMatrix();
  Eigen::Matrix3d axes;
  axes.row(0) = UnrealDirection(r.row(2).transpose());   // forward
  axes.row(1) = UnrealDirection(r.row(0).transpose());   // right
  axes.row(2) = UnrealDirection(-r.row(1).transpose());  // up
  *rotation = UnrealRotatorFromAxes(axes);
  *location_cm = UnrealFromEnuMetres(CameraCenterInWorld(cam_from_enu));
}

OrientedBox EnuBoxOfUnrealBox(const Eigen::Vector3d& center_cm,
                              const Eigen::Vector3d& extent_cm,
                              const UnrealRotator& rotation) {
  const Eigen::Matrix3d axes = UnrealAxes(rotation);
  OrientedBox box;
  box.center = EnuMetresFromUnreal(center_cm);
  const double m = Unreal().metres_per_unit;
  box.half_extents = {extent_cm.y() * m, extent_cm.x() * m, extent_cm.z() * m};
  box.world_from_box.col(0) = EnuDirection(axes.row(1).transpose());
  box.world_from_box.col(1) = EnuDirection(axes.row(0).transpose());
  box.world_from_box.col(2) = EnuDirection(axes.row(2).transpose());
  return box;
}

void UnrealBoxOfEnuBox(const OrientedBox& box,
                       Eigen::Vector3d* center_cm,
                       Eigen::Vector3d* extent_cm,
                       UnrealRotator* rotation) {
  *center_cm = UnrealFromEnuMetres(box.center);
  const double m = Unreal().metres_per_unit;
  *extent_cm =
      Eigen::Vector3d(box.half_extents.y() / m, box.half_extents.x() / m, box.half_extents.z() / m);
  Eigen::Matrix3d axes;
  axes.row(0) = UnrealDirection(box.world_from_box.col(1));
  axes.row(1) = UnrealDirection(box.world_from_box.col(0));
  axes.row(2) = UnrealDirection(box.world_from_box.col(2));
  *rotation = UnrealRotatorFromAxes(axes);
}

}  // namespace lsds::import
