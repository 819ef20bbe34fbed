#include "importers/derived_truth.h"

#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace lsds::import {

std::optional<double> RayEntersBox(const OrientedBox& box,
                                   const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& direction) {
  // Slab test in the box frame.
  const Eigen::Vector3d o = box.world_from_box.transpose() * (origin - box.center);
  const Eigen::Vector3d d = box.world_from_box.transpose() * direction;
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double h = box.half_extents[axis];
    if (std::abs(d[axis]) < 1e-300) {
      if (std::abs(o[axis]) > h) return std::nullopt;
      continue;
    }
    double t0 = (-h - o[axis]) / d[axis];
    double t1 = (h - o[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
  }
  // Entered from outside in front of the camera, as a renderer sees it.
  if (t_near <= t_far && t_near > 1e-9) return t_near;
  return std::nullopt;
}

exr::FlatImage ConvertDepthKind(const exr::FlatImage& depth,
                                DepthKind from,
                                DepthKind to,
                                const PinholeCamera& camera) {
  exr::FlatImage out(depth.width(), depth.height());
  std::vector<float>& z = out.AddChannel("Z", exr::PixelType::kFloat).floats;
  const std::vector<float>& in = depth.Get("Z").floats;
  for (int j = 0; j < depth.height(); ++j) {
    for (int i = 0; i < depth.width(); ++i) {
      const size_t p = depth.Index(i, j);
      const Eigen::Vector2d pixel(i + 0.5, j + 0.5);
      if (from == to || !std::isfinite(in[p])) {
        z[p] = in[p];
      } else if (from == DepthKind::kPlanar) {
        z[p] = static_cast<float>(PerspectiveFromPlanarDepth(camera, pixel, in[p]));
      } else {
        z[p] = static_cast<float>(PlanarFromPerspectiveDepth(camera, pixel, in[p]));
      }
    }
  }
  return out;
}

int64_t CountObbPixels(const OrientedBox& box,
                       const PinholeCamera& camera,
                       const Rigid3d& cam_from_world,
                       const Box2d& bounds) {
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const int i0 = std::max(0, static_cast<int>(std::floor(bounds.x0)));
  const int j0 = std::max(0, static_cast<int>(std::floor(bounds.y0)));
  const int i1 = std::min(camera.width, static_cast<int>(std::ceil(bounds.x1)));
  const int j1 = std::min(camera.height, static_cast<int>(std::ceil(bounds.y1)));
  int64_t count = 0;
  for (int j = j0; j < j1; ++j) {
    for (int i = i0; i < i1; ++i) {
      const Eigen::Vector3d direction =
          world_from_cam.rotation * camera.RayThroughPixelCenter(i, j);
      if (RayEntersBox(box, world_from_cam.translation, direction)) ++count;
    }
  }
  return count;
}

}  // namespace lsds::import
