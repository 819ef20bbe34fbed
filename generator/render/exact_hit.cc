#include "generator/render/exact_hit.h"

#include <cmath>
#include <cstddef>

#include <Eigen/Geometry>

#include "generator/scene/world_ground.h"

namespace lsds::gen {

ExactHit ResolveExactHit(const RenderScene& scene,
                         const EmbreeHit& rh,
                         const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& direction,
                         TrianglePlane* plane) {
  ExactHit hit;
  if (rh.geom == RTC_INVALID_GEOMETRY_ID) {
    // Past the world ground's skirt: the plane it settles to
    // (generator/scene/world_ground.h), exact in double.
    if (scene.ground_plane() >= 0 && direction.z() < 0 && origin.z() > kWorldGroundZ) {
      hit.hit = true;
      hit.geom = static_cast<unsigned>(scene.ground_plane());
      hit.t = (kWorldGroundZ - origin.z()) / direction.z();
      hit.point = origin + hit.t * direction;
      hit.point.z() = kWorldGroundZ;
      hit.normal = hit.shading_normal = Eigen::Vector3d::UnitZ();
    }
    return hit;
  }
  hit.hit = true;
  hit.geom = rh.geom;
  hit.prim = rh.prim;
  hit.u = rh.u;
  hit.v = rh.v;
  const Surface& s = scene.surface(rh.geom);
  if (plane->geom != rh.geom || plane->prim != rh.prim) {
    const Eigen::Vector3i& tri = s.triangles[rh.prim];
    const Eigen::Vector3d v0 = s.positions[tri[0]].cast<double>();
    const Eigen::Vector3d v1 = s.positions[tri[1]].cast<double>();
    const Eigen::Vector3d v2 = s.positions[tri[2]].cast<double>();
    const Eigen::Vector3d n = (v1 - v0).cross(v2 - v0);
    const double nn = n.norm();
    plane->geom = rh.geom;
    plane->prim = rh.prim;
    plane->normal = nn > 0 ? Eigen::Vector3d(n / nn) : Eigen::Vector3d(0, 0, 1);
    plane->offset = plane->normal.dot(v0 - origin);
  }
  Eigen::Vector3d n = plane->normal;
  const double nd = n.dot(direction);
  hit.t = std::abs(nd) > 1e-12 ? plane->offset / nd : rh.tfar;
  if (!(hit.t > 0)) hit.t = rh.tfar;
  if (nd > 0) n = -n;
  hit.normal = n;
  hit.point = origin + hit.t * direction;
  hit.shading_normal = n;
  if (s.corner_normals != nullptr) {
    const Eigen::Vector3f* c = s.corner_normals + 3 * static_cast<size_t>(rh.prim);
    const float u = rh.u, v = rh.v;
    const Eigen::Vector3d smooth = ((1 - u - v) * c[0] + u * c[1] + v * c[2]).cast<double>();
    const double len = smooth.norm();
    if (len > 0) hit.shading_normal = (smooth.dot(n) < 0 ? -smooth : smooth) / len;
  }
  return hit;
}

}  // namespace lsds::gen
