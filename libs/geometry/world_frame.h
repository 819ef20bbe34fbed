// The world frame a collection declares (docs/format.md, "Units and frames").
// Tools convert declared coordinates to the canonical frame, ENU metres
// (right-handed, z up), and work there.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "libs/geometry/rigid3.h"

namespace lsds {

struct WorldFrame {
  std::string name = "ENU";       // "ENU" | "NED" | "unreal"
  std::string length_unit = "m";  // "m" | "cm" | "mm"
  double metres_per_unit = 1.0;
  // Axis mapping to ENU; determinant -1 for a left-handed frame (Unreal: x
  // north, y east, z up).
  Eigen::Matrix3d enu_from_frame = Eigen::Matrix3d::Identity();

  // Throws lsds::Error for unknown names; `valid_names` lists them for messages
  // and schemas.
  static WorldFrame Make(const std::string& name, const std::string& length_unit);
  static const std::vector<std::string>& FrameNames();
  static const std::vector<std::string>& UnitNames();

  bool right_handed() const { return enu_from_frame.determinant() > 0; }

  Eigen::Vector3d EnuMetresFromWorld(const Eigen::Vector3d& point_in_world) const {
    return metres_per_unit * (enu_from_frame * point_in_world);
  }
  Eigen::Vector3d WorldFromEnuMetres(const Eigen::Vector3d& point_in_enu) const {
    return enu_from_frame.transpose() * point_in_enu / metres_per_unit;
  }
  // A declared camera pose (orthogonal `rotation`, translation in world units;
  // the camera frame is OpenCV, in the same unit) as a proper rigid transform
  // from ENU metres to the camera in metres.
  Rigid3d CamFromEnuMetres(const Eigen::Matrix3d& cam_from_world_rotation,
                           const Eigen::Vector3d& cam_from_world_translation) const;
};

}  // namespace lsds
