#include "libs/geometry/attitude.h"

#include <cmath>

namespace lsds {

namespace {
constexpr double kPi = 3.14159265358979323846;
double Rad(double deg) { return deg * kPi / 180.0; }
double Deg(double rad) { return rad * 180.0 / kPi; }
}  // namespace

Eigen::Quaterniond NedFromBody(const Attitude& attitude) {
  return Eigen::AngleAxisd(Rad(attitude.yaw_deg), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(Rad(attitude.pitch_deg), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(Rad(attitude.roll_deg), Eigen::Vector3d::UnitX());
}

Attitude AttitudeFromNedFromBody(const Eigen::Quaterniond& ned_from_body) {
  const Eigen::Matrix3d r = ned_from_body.toRotationMatrix();
  Attitude attitude;
  // r = Rz(y) Ry(p) Rx(r): r(2,0) = -sin(p).
  const double sin_pitch = std::max(-1.0, std::min(1.0, -r(2, 0)));
  attitude.pitch_deg = Deg(std::asin(sin_pitch));
  if (std::abs(sin_pitch) < 1.0 - 1e-12) {
    attitude.roll_deg = Deg(std::atan2(r(2, 1), r(2, 2)));
    attitude.yaw_deg = Deg(std::atan2(r(1, 0), r(0, 0)));
  } else {
    // Gimbal lock (nadir or zenith): only yaw -/+ roll is defined; put it all
    // in yaw.
    attitude.roll_deg = 0.0;
    attitude.yaw_deg = Deg(std::atan2(-r(0, 1), r(1, 1)));
  }
  return attitude;
}

Eigen::Matrix3d BodyFromCam() {
  Eigen::Matrix3d body_from_cam;
  // Columns are the camera axes in the body frame: cam x = body y, cam y = body
  // z, cam z = body x.
  body_from_cam << 0, 0, 1,  //
      1, 0, 0,               //
      0, 1, 0;
  return body_from_cam;
}

Eigen::Matrix3d EnuFromNed() {
  Eigen::Matrix3d enu_from_ned;
  enu_from_ned << 0, 1, 0,  //
      1, 0, 0,              //
      0, 0, -1;
  return enu_from_ned;
}

Rigid3d CamFromEnu(const Eigen::Vector3d& position_in_enu, const Attitude& attitude) {
  const Eigen::Matrix3d enu_from_cam =
      EnuFromNed() * NedFromBody(attitude).toRotationMatrix() * BodyFromCam();
  return Rigid3d(Eigen::Quaterniond(enu_from_cam), position_in_enu).Inverse();
}

void PositionAndAttitudeFromCamFromEnu(const Rigid3d& cam_from_enu,
                                       Eigen::Vector3d* position_in_enu,
                                       Attitude* attitude) {
  const Rigid3d enu_from_cam = cam_from_enu.Inverse();
  *position_in_enu = enu_from_cam.translation;
  const Eigen::Matrix3d ned_from_body =
      EnuFromNed() * enu_from_cam.rotation.toRotationMatrix() * BodyFromCam().transpose();
  *attitude = AttitudeFromNedFromBody(Eigen::Quaterniond(ned_from_body));
}

}  // namespace lsds
