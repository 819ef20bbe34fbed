// What the capture's camera sets for every frame (docs/languages.md, "Camera settings"): the
// intrinsics, the frame rate, how waypoint heights are read and the clearance the camera keeps;
// and what it sets in the plan (exposure, rig, post-process materials, capture settings).
#pragma once

#include <optional>

#include "generator/lang/scene.h"
#include "generator/plan/plan.h"
#include "libs/geometry/camera.h"

namespace lsds {

// Default minimum clearance of a camera above the terrain and objects (docs/languages.md,
// "Cameras where a drone can be").
inline constexpr double kDefaultClearanceM = 1.0;

struct CameraSetup {
  const Definition* camera = nullptr;  // the capture's camera; null: the default one
  PinholeCamera intrinsics = PinholeCamera::FromHorizontalFov(1024, 1024, 60);
  double fps = 10;
  bool heights_agl = false;  // waypoint and point z above the terrain (heights:agl)
  std::optional<double> clearance_m = kDefaultClearanceM;  // none: clearance:off
};

// The camera's settings, each checked at its place; sets plan->exposure, rig, post_process and
// capture_settings. `camera` may be null (the defaults, nothing set in the plan).
CameraSetup ReadCameraSetup(const Definition* camera, Plan* plan);

// The camera's exposure (docs/languages.md, "Exposure"): `ev100`, or `shutter` (s) with
// `f_number` and `iso` (default 100); neither: auto exposure, with `iso` and `f_number` fixed if
// given.
PlannedExposure ReadExposure(const Node& settings);

}  // namespace lsds
