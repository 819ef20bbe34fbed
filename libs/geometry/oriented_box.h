// 3D oriented bounding boxes (OBBs) and their projection into a pinhole camera.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "libs/geometry/box2d.h"
#include "libs/geometry/camera.h"
#include "libs/geometry/rigid3.h"

namespace lsds {

struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();              // point_in_world
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();        // along the box axes
  Eigen::Matrix3d world_from_box = Eigen::Matrix3d::Identity();  // columns: box axes in the world

  // Corner k has sign (+/-) of half_extents from bits 0, 1, 2 of k.
  std::array<Eigen::Vector3d, 8> Corners() const;
  bool Contains(const Eigen::Vector3d& point_in_world, double tolerance = 0.0) const;
  // Separating-axis test; touching boxes do not intersect.
  bool Intersects(const OrientedBox& other) const;
};

// The image points of the box's projected silhouette: the corners in front of
// the near plane z = `near` and the points where the box's edges cross it
// (unclipped to the image; empty when the box is entirely behind the plane).
// Their bounds are ProjectedBounds, their convex hull the silhouette of
// InFrameFraction, their minimum-area rectangle the amodal oriented box of the
// object truth.
std::vector<Eigen::Vector2d> ProjectedSilhouettePoints(const OrientedBox& box,
                                                       const PinholeCamera& camera,
                                                       const Rigid3d& cam_from_world,
                                                       double near = 1e-3);

// The pixel-edge bounding box of the box's projection, clipped at the near
// plane z = `near` (unclipped to the image). Empty when the box is entirely
// behind the near plane.
std::optional<Box2d> ProjectedBounds(const OrientedBox& box,
                                     const PinholeCamera& camera,
                                     const Rigid3d& cam_from_world,
                                     double near = 1e-3);

// Fraction of the box's projected silhouette (the convex hull of its projected
// corners) that lies inside the image; 0 when the box is behind the camera.
// Boxes crossing the near plane are clipped.
double InFrameFraction(const OrientedBox& box,
                       const PinholeCamera& camera,
                       const Rigid3d& cam_from_world,
                       double near = 1e-3);

}  // namespace lsds
