// A camera ray's exact hit, from what Embree reports: Embree finds the
// triangle, the plane of its (float) vertices then gives the distance in
// double, so a flat terrain at z = 0 yields z == 0 and depth == altitude to
// double precision. The integrator resolves each sample's hit here.
#pragma once

#include <embree3/rtcore.h>
#include <Eigen/Core>

#include "generator/render/embree_scene.h"
#include "generator/render/ray_casts.h"

namespace lsds::gen {

struct ExactHit {
  bool hit = false;
  unsigned geom = 0;
  double t = 0;            // along the ray whose camera-frame direction has z == 1: planar depth
  Eigen::Vector3d point;   // world
  Eigen::Vector3d normal;  // world, unit, facing the camera
  // Interpolated corner normal (smooth shading), on the camera's side; used
  // for lighting only, the normal layer keeps `normal`.
  Eigen::Vector3d shading_normal;
  unsigned prim = 0;  // Embree's triangle and barycentrics: texture lookups
  float u = 0, v = 0;
};

// The plane of the triangle a tile last resolved, for rays from one origin:
// neighbouring samples mostly hit the same triangle, whose unit normal (a
// cross product and a square root) is then computed once. The same doubles
// either way.
struct TrianglePlane {
  unsigned geom = RTC_INVALID_GEOMETRY_ID, prim = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, as the vertices wind
  double offset = 0;                                  // normal . (v0 - origin)
};

// The exact hit of the ray from `origin` along `direction` (world) whose
// Embree hit is `embree_hit`; a ray that misses every triangle but falls past
// the world ground's skirt hits the plane it settles to
// (generator/scene/world_ground.h). `plane` is the caller's cache, one per
// origin.
ExactHit ResolveExactHit(const RenderScene& scene,
                         const EmbreeHit& embree_hit,
                         const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& direction,
                         TrianglePlane* plane);

}  // namespace lsds::gen
