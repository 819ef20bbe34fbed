// What the report says about a frame's camera: altitude above the surface
// seen, off-nadir angle and ground sample distance, computed from the camera
// truth and the depth at the image centre (docs/report.md).
#pragma once

#include <optional>

#include "libs/collection/model.h"
#include "libs/exr/flat_image.h"

namespace lsds::report {

struct FrameCamera {
  Eigen::Vector3d center_in_enu = Eigen::Vector3d::Zero();  // metres
  double height_m = 0;  // camera centre above the world's z = 0 datum (ENU up)
  // Angle between the optical axis and straight down, degrees: 0 = nadir.
  double off_nadir_deg = 0;
  // From the surface seen at the principal point (NaN when that pixel is sky
  // or the axis misses the datum): camera height above that surface point,
  // distance along the line of sight, and the ground sample distance there
  // (distance / focal length in pixels, for a surface facing the camera).
  double altitude_m = 0.0 / 0.0;
  double distance_m = 0.0 / 0.0;
  double gsd_m = 0.0 / 0.0;
  bool from_depth = false;  // false: the axis was intersected with z = 0
};

// Pose of the camera as a proper rigid transform from ENU metres.
Rigid3d CamFromEnuMetres(const CollectionHeader& header, const Frame& frame);

// `depth` is the frame's depth layer (channel Z) or null; without it the
// optical axis is intersected with the datum plane z = 0.
FrameCamera ComputeFrameCamera(const CollectionHeader& header,
                               const Frame& frame,
                               const exr::FlatImage* depth,
                               std::optional<DepthKind> depth_kind);

// Distance in metres from the camera centre to the centre of an object's OBB;
// NaN for an object without one (shown as n/a, left out of histograms).
double ObjectDistanceM(const CollectionHeader& header,
                       const FrameCamera& camera,
                       const ObjectTruth& object);

}  // namespace lsds::report
