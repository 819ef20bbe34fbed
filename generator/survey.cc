#include "generator/survey.h"

#include "generator/plan/terrain_height.h"

namespace lsds::gen {

void AddSurveyMetadata(const Plan& plan, const PlannedFrame& frame, MetadataFrame* metadata) {
  const PinholeCamera& camera = frame.camera;
  const PlannedTerrain terrain = TerrainAt(plan, frame);  // LCAP may change its shape
  const Eigen::Vector3d eye = CameraCenterInWorld(frame.cam_from_world);
  const Eigen::Matrix3d world_from_cam =
      frame.cam_from_world.rotation.conjugate().toRotationMatrix();
  auto ground_at = [&](double u, double v) {
    const Eigen::Vector3d ray = world_from_cam * camera.CamFromImage(Eigen::Vector2d(u, v));
    return IntersectTerrain(terrain, eye, ray, kSurveyMaxRangeM);
  };
  metadata->altitude_agl_m = eye.z() - TerrainHeight(terrain, eye.x(), eye.y());
  // GSD at the principal point: the size of one pixel across the ray at the
  // ground it sees (range / fx); for a nadir view over flat ground, AGL / fx.
  if (const auto centre = ground_at(camera.cx, camera.cy))
    metadata->gsd_m = (*centre - eye).norm() / camera.fx;
  std::vector<Eigen::Vector3d> corners;
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0, 0),
                                        Eigen::Vector2d(camera.width, 0),
                                        Eigen::Vector2d(camera.width, camera.height),
                                        Eigen::Vector2d(0, camera.height)}) {
    const auto hit = ground_at(corner.x(), corner.y());
    if (!hit) {
      corners.clear();  // a corner above the horizon: no footprint polygon
      break;
    }
    corners.push_back(*hit);
  }
  metadata->footprint = corners;
  if (plan.geo) metadata->geo = GeodeticOf(*plan.geo, eye);
}

}  // namespace lsds::gen
