#include "report/frame_camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lsds::report {

Rigid3d CamFromEnuMetres(const CollectionHeader& header, const Frame& frame) {
  return header.conventions.world.CamFromEnuMetres(frame.camera.cam_from_world_rotation,
                                                   frame.camera.cam_from_world_translation);
}

FrameCamera ComputeFrameCamera(const CollectionHeader& header,
                               const Frame& frame,
                               const exr::FlatImage* depth,
                               std::optional<DepthKind> depth_kind) {
  const Rigid3d cam_from_enu = CamFromEnuMetres(header, frame);
  const Rigid3d enu_from_cam = cam_from_enu.Inverse();
  const PinholeCamera& intrinsics = frame.camera.intrinsics;
  FrameCamera out;
  out.center_in_enu = enu_from_cam.translation;
  out.height_m = out.center_in_enu.z();
  const Eigen::Vector3d axis_in_enu =
      (enu_from_cam.rotation * Eigen::Vector3d::UnitZ()).normalized();
  out.off_nadir_deg = std::acos(std::clamp(-axis_in_enu.z(), -1.0, 1.0)) * 180.0 / M_PI;

  // The pixel holding the principal point; its ray is (nearly) the axis.
  const int i =
      std::clamp(static_cast<int>(std::floor(intrinsics.cx)), 0, std::max(0, intrinsics.width - 1));
  const int j = std::clamp(
      static_cast<int>(std::floor(intrinsics.cy)), 0, std::max(0, intrinsics.height - 1));
  const Eigen::Vector2d pixel(i + 0.5, j + 0.5);
  std::optional<Eigen::Vector3d> point_in_cam;  // metres
  if (depth != nullptr && depth->Find("Z") != nullptr && i < depth->width() &&
      j < depth->height()) {
    out.from_depth = true;
    const double value =
        depth->Get("Z").floats[depth->Index(i, j)] * header.conventions.world.metres_per_unit;
    if (std::isfinite(value) && value > 0) {
      point_in_cam =
          UnprojectDepth(intrinsics, pixel, value, depth_kind.value_or(DepthKind::kPlanar));
    }
  } else {
    // No depth: where the ray meets the datum plane z = 0, if it goes down.
    const Eigen::Vector3d ray_in_enu = enu_from_cam.rotation * intrinsics.CamFromImage(pixel);
    if (ray_in_enu.z() < 0) {
      point_in_cam = intrinsics.CamFromImage(pixel) * (out.center_in_enu.z() / -ray_in_enu.z());
    }
  }
  if (point_in_cam) {
    const Eigen::Vector3d point_in_enu = enu_from_cam * *point_in_cam;
    out.altitude_m = out.center_in_enu.z() - point_in_enu.z();
    out.distance_m = point_in_cam->norm();
    out.gsd_m = out.distance_m / intrinsics.fx;
  }
  return out;
}

double ObjectDistanceM(const CollectionHeader& header,
                       const FrameCamera& camera,
                       const ObjectTruth& object) {
  if (!object.obb) return std::numeric_limits<double>::quiet_NaN();
  return (header.conventions.world.EnuMetresFromWorld(object.obb->center) - camera.center_in_enu)
      .norm();
}

}  // namespace lsds::report
