// LCAP camera rigs (docs/languages.md, "Camera rigs"): several cameras with
// fixed poses relative to the platform, each with its own intrinsics, moving
// together along the capture's paths.
#pragma once

#include <optional>

#include "generator/lang/values.h"
#include "libs/collection/model.h"
#include "libs/geometry/camera.h"

namespace lsds {

// The intrinsics part of Camera Settings: resolution, horizontal field of
// view, or focal length and sensor width (mm). A rig camera starts from the
// capture camera's settings and overrides what its own settings give.
struct IntrinsicSettings {
  int width = 1024, height = 1024;
  double fov_deg = 60;
  std::optional<double> focal_mm;
  double sensor_mm = 36;

  // Reads `res`/`resolution`, `fov`, `focal_length`, `sensor_width` of
  // `settings`, each checked at its place.
  void Read(const Node& settings);
  PinholeCamera Camera() const;
};

// The Camera Settings keys that describe intrinsics (a rig camera may set
// only these: fps, clearance and heights belong to the platform).
const std::vector<std::string>& IntrinsicSettingKeys();

// The camera's `rig:{NAME:{position:[x,y,z], attitude:[roll,pitch,yaw],
// csettings:{...}}, ...}`, cameras in the order written. `position` is in the
// platform frame (the OpenCV frame of the pose the path gives: x right, y down,
// z along the view; metres); `attitude` turns the camera relative to the
// platform in the attitude convention of libs/geometry/attitude.h (pitch up
// towards the image top, yaw towards the image right, roll about the view).
Rig ReadRig(const Node& rig, const IntrinsicSettings& platform);

// rig_from_cam of a camera at `position` with `attitude` relative to the
// platform (as ReadRig reads them).
Rigid3d RigFromCam(const Eigen::Vector3d& position, const Attitude& attitude);

}  // namespace lsds
