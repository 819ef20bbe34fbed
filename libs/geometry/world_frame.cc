#include "libs/geometry/world_frame.h"

#include "libs/geometry/attitude.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {

const std::vector<std::string>& WorldFrame::FrameNames() {
  static const std::vector<std::string> names = {"ENU", "NED", "unreal"};
  return names;
}

const std::vector<std::string>& WorldFrame::UnitNames() {
  static const std::vector<std::string> names = {"m", "cm", "mm"};
  return names;
}

WorldFrame WorldFrame::Make(const std::string& name, const std::string& length_unit) {
  WorldFrame frame;
  frame.name = name;
  frame.length_unit = length_unit;
  if (name == "ENU") {
    frame.enu_from_frame.setIdentity();
  } else if (name == "NED") {
    frame.enu_from_frame = EnuFromNed();
  } else if (name == "unreal") {
    // Unreal Engine: x forward (north), y right (east), z up; left-handed.
    frame.enu_from_frame << 0, 1, 0,  //
        1, 0, 0,                      //
        0, 0, 1;
  } else {
    throw Error("unknown world frame '" + name + "'" + DidYouMean(name, FrameNames()) +
                "; expected one of " + Join(FrameNames(), ", "));
  }
  if (length_unit == "m") {
    frame.metres_per_unit = 1.0;
  } else if (length_unit == "cm") {
    frame.metres_per_unit = 0.01;
  } else if (length_unit == "mm") {
    frame.metres_per_unit = 0.001;
  } else {
    throw Error("unknown length unit '" + length_unit + "'" + DidYouMean(length_unit, UnitNames()) +
                "; expected one of " + Join(UnitNames(), ", "));
  }
  return frame;
}

Rigid3d WorldFrame::CamFromEnuMetres(const Eigen::Matrix3d& cam_from_world_rotation,
                                     const Eigen::Vector3d& cam_from_world_translation) const {
  // p_cam[unit] = R p_world + t,  p_world = F^T p_enu / s   =>   p_cam[m] = R
  // F^T p_enu + s t.
  const Eigen::Matrix3d rotation = cam_from_world_rotation * enu_from_frame.transpose();
  return Rigid3d(Eigen::Quaterniond(rotation), metres_per_unit * cam_from_world_translation);
}

}  // namespace lsds
