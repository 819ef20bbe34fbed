// Unreal Engine's conventions mapped to the collection's (docs/import.md,
// "UE5 Movie Render Queue"): the world is left-handed, x forward (north), y
// right (east), z up, centimetres (the `unreal` world frame of
// libs/geometry/world_frame.h); rotations are FRotator (pitch, yaw, roll in
// degrees) whose FRotationMatrix rows are the rotated X (forward), Y (right)
// and Z (up) axes; a camera looks along its X with Y right and Z up.
#pragma once

#include <Eigen/Core>

#include "libs/geometry/oriented_box.h"
#include "libs/geometry/rigid3.h"

namespace lsds::import {

struct UnrealRotator {
  double pitch = 0, yaw = 0, roll = 0;  // degrees
};

// FRotationMatrix: rows are the X, Y, Z axes in Unreal world coordinates.
Eigen::Matrix3d UnrealAxes(const UnrealRotator& rotator);
// FMatrix::Rotator: the rotator of orthonormal axes (rows X, Y, Z).
UnrealRotator UnrealRotatorFromAxes(const Eigen::Matrix3d& axes);

// A point in Unreal world centimetres in ENU metres, and back.
Eigen::Vector3d EnuMetresFromUnreal(const Eigen::Vector3d& point_in_unreal_cm);
Eigen::Vector3d UnrealFromEnuMetres(const Eigen::Vector3d& point_in_enu_m);

// An Unreal camera (location in cm, rotation) as the OpenCV cam_from_world
// pose of the ENU metre world (rotation determinant +1), and back.
Rigid3d CamFromEnuOfUnrealCamera(const Eigen::Vector3d& location_cm, const UnrealRotator& rotation);
void UnrealCameraOfCamFromEnu(const Rigid3d& cam_from_enu,
                              Eigen::Vector3d* location_cm,
                              UnrealRotator* rotation);

// An Unreal box (centre in cm, half extents in cm along its X, Y, Z axes,
// rotation) as an OBB in ENU metres, and back. Unreal's X, Y, Z axes map to a
// left-handed triple in ENU, so the OBB's first two axes are Unreal's Y and X
// (half extents swapped alike): the same box with a proper rotation.
OrientedBox EnuBoxOfUnrealBox(const Eigen::Vector3d& center_cm,
                              const Eigen::Vector3d& extent_cm,
                              const UnrealRotator& rotation);
void UnrealBoxOfEnuBox(const OrientedBox& box,
                       Eigen::Vector3d* center_cm,
                       Eigen::Vector3d* extent_cm,
                       UnrealRotator* rotation);

}  // namespace lsds::import
