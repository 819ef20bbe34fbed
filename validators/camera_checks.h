// Camera geometry: does the declared pinhole camera explain the world-position
// and depth layers? When it does not, Ceres (in a plug-in) solves for the intrinsics (and then
// the pose) that do, and the common mistakes are diagnosed by name: wrong FOV
// or focal unit, depth in cm vs m, planar vs perspective depth, a mirrored
// world axis (handedness), an image stored upside down.
#pragma once

#include <string>
#include <vector>

#include "libs/collection/model.h"
#include "libs/exr/flat_image.h"
#include "validators/camera_solver_abi.h"  // CameraSolution
#include "validators/checks.h"
#include "validators/finding.h"
#include "validators/report.h"

namespace lsds::validate {

struct CameraCheckInput {
  const Frame* frame = nullptr;
  const exr::FlatImage* worldposition = nullptr;  // channels X, Y, Z
  std::string worldposition_file;
  const exr::FlatImage* depth = nullptr;  // channel Z; may be null
  std::string depth_channel = "Z";
  std::string depth_file;
  DepthKind depth_kind = DepthKind::kPlanar;
  int grid = 24;  // correspondences per image axis
};

// Appends findings of the camera.* checks selected; returns the declared
// camera's RMS reprojection error in pixels (statistic
// "camera.reprojection_rms_px").
double CheckCameraGeometry(const CameraCheckInput& input,
                           const CheckSelection& checks,
                           std::vector<Finding>* findings);

// Exposed for tests: solve intrinsics (and the pose when `solve_pose`) from
// correspondences, starting at `initial`, with a Cauchy loss. Ceres runs in the
// lsds_camera_solver plug-in, opened on the first call (throws lsds::Error when
// it cannot be loaded).
CameraSolution SolveCamera(const std::vector<Eigen::Vector2d>& pixels,
                           const std::vector<Eigen::Vector3d>& points_in_world,
                           const CameraSolution& initial,
                           bool solve_pose);

}  // namespace lsds::validate
