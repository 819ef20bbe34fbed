// Platform attitude as roll/pitch/yaw, the way GNSS/INS metadata states it.
//
// Aerospace convention: NED world, FRD body (x forward, y right, z down),
//   ned_from_body = Rz(yaw) * Ry(pitch) * Rx(roll)     (intrinsic z-y'-x'')
// yaw from north, clockwise positive; pitch nose-up positive; roll
// right-wing-down positive; degrees. The camera looks along body x: the OpenCV
// camera frame (x right, y down, z forward) is the FRD body frame with its axes
// renamed, so a nadir camera has pitch = -90.
#pragma once

#include <Eigen/Geometry>

#include "libs/geometry/rigid3.h"

namespace lsds {

struct Attitude {
  double roll_deg = 0;
  double pitch_deg = 0;
  double yaw_deg = 0;
};

Eigen::Quaterniond NedFromBody(const Attitude& attitude);
Attitude AttitudeFromNedFromBody(const Eigen::Quaterniond& ned_from_body);

// Rotation from the OpenCV camera frame to the body frame (a fixed axis
// permutation).
Eigen::Matrix3d BodyFromCam();
// Rotation from NED to ENU (swap x/y, flip z); its own inverse.
Eigen::Matrix3d EnuFromNed();

// Pose of a camera at `position_in_enu` with the given attitude, in an ENU
// world.
Rigid3d CamFromEnu(const Eigen::Vector3d& position_in_enu, const Attitude& attitude);
// Inverse of CamFromEnu: camera centre and attitude of a pose.
void PositionAndAttitudeFromCamFromEnu(const Rigid3d& cam_from_enu,
                                       Eigen::Vector3d* position_in_enu,
                                       Attitude* attitude);

}  // namespace lsds
