#include "generator/lang/capture/clearance.h"

#include "generator/plan/terrain_height.h"
#include "libs/geometry/oriented_box.h"
#include "libs/util/strings.h"

namespace lsds {

void CheckClearance(const Plan& plan,
                    const PlannedTerrain& terrain,
                    double clearance_m,
                    const Rigid3d& cam_from_world,
                    const std::function<std::string()>& pose,
                    const Node& where) {
  const Eigen::Vector3d eye = CameraCenterInWorld(cam_from_world);
  const std::string fix = "; raise the path, or set camera settings clearance:" +
                          std::string("N (metres) or clearance:off");
  if (terrain.present) {
    const double ground = TerrainHeight(terrain, eye.x(), eye.y());
    if (eye.z() < ground + clearance_m)
      where.Fail(pose() + ": the camera at (" + FormatNumber(eye.x()) + ", " +
                 FormatNumber(eye.y()) + ", " + FormatNumber(eye.z()) + ") is " +
                 FormatNumber(eye.z() - ground) + " m above the terrain (height " +
                 FormatNumber(ground) + " m there), under the clearance of " +
                 FormatNumber(clearance_m) + " m" + fix);
  }
  for (const PlannedObject& o : plan.objects) {
    if (!o.visible) continue;
    const OrientedBox grown{
        o.position, 0.5 * o.extent + Eigen::Vector3d::Constant(clearance_m), o.world_from_object};
    const Eigen::Vector3d local = grown.world_from_box.transpose() * (eye - grown.center);
    if ((local.cwiseAbs() - grown.half_extents).maxCoeff() < 0)
      where.Fail(pose() + ": the camera is within " + FormatNumber(clearance_m) + " m of object " +
                 o.name + fix);
  }
}

}  // namespace lsds
