// Truth derived from layers, for sources that do not store it (docs/import.md,
// "Derived truth"). 2D boxes and pixel counts come from the id layer through
// libs/collection/object_truth.h; depth conversions and unprojection are those
// of libs/geometry/camera.h.
#pragma once

#include <cstdint>
#include <optional>

#include "libs/collection/model.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/box2d.h"
#include "libs/geometry/camera.h"
#include "libs/geometry/oriented_box.h"
#include "libs/geometry/rigid3.h"

namespace lsds::import {

// The worldposition layer of a depth layer is PredictWorldPosition
// (libs/collection/worldposition_layout.h).

// A depth layer of `kind` from one of the other kind (planar <-> perspective).
exr::FlatImage ConvertDepthKind(const exr::FlatImage& depth,
                                DepthKind from,
                                DepthKind to,
                                const PinholeCamera& camera);

// Where the ray origin + t * direction (t > 0) enters `box` from outside:
// t at the entry, or none when it misses the box or starts inside it.
std::optional<double> RayEntersBox(const OrientedBox& box,
                                   const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& direction);

// The pixels inside `bounds` whose centre ray hits `box` in front of the
// camera: the pixels the object would cover with no occluder when it fills its
// OBB (exact for box-shaped objects; otherwise an upper bound, so the
// visibility measured with it is a lower bound).
int64_t CountObbPixels(const OrientedBox& box,
                       const PinholeCamera& camera,
                       const Rigid3d& cam_from_world,
                       const Box2d& bounds);

}  // namespace lsds::import
