// Spatial relations of LSCENE placement (docs/languages.md, "Position:
// Algorithm 1"), after Scenic's vocabulary: NEAR, BEHIND, IN FRONT OF (where an
// object's centre may lie relative to another object) and FACING (which way it
// turns). All are horizontal: a UAV scene's objects stand on the ground, their
// height comes from what they stand on.
#pragma once

#include <limits>
#include <string>

#include <Eigen/Core>

#include "libs/geometry/oriented_box.h"

namespace lsds {

// A region of the horizontal plane the placed object's centre must lie in.
struct Relation {
  enum class Kind { kNear, kBehind, kInFront };
  Kind kind = Kind::kNear;
  Eigen::Vector2d ref_xy = Eigen::Vector2d::Zero();        // the reference's centre
  Eigen::Vector2d ref_heading = Eigen::Vector2d::UnitX();  // its forward (+x) direction, unit
  // Centre-to-centre horizontal distance bound (NEAR; optional for the others).
  double distance = std::numeric_limits<double>::infinity();
};

// Whether a centre at `point_in_world` satisfies the relation.
bool RelationHolds(const Relation& relation, const Eigen::Vector3d& point_in_world);

// The axis-aligned x, y bounds of the relation's region (infinite where it is
// unbounded), to shrink Algorithm 1's box before the draws.
void RelationBounds(const Relation& relation, Eigen::Vector2d* lo, Eigen::Vector2d* hi);

// An object's heading: its +x axis projected on the ground, unit; +x of the
// world when that axis is vertical.
Eigen::Vector2d HeadingOf(const Eigen::Matrix3d& world_from_object);

// `world_from_object` turned about the vertical so that the heading points from
// `from` toward `toward` (unchanged when they share x and y). Roll and pitch
// are kept.
Eigen::Matrix3d FacingRotation(const Eigen::Matrix3d& world_from_object,
                               const Eigen::Vector3d& from,
                               const Eigen::Vector3d& toward);

// The largest horizontal distance of the box's corners from its centre: the
// half-width a turn about the vertical can never exceed, so a FACING object
// sampled with it stays in the space whatever way it turns.
double HorizontalRadius(const Eigen::Matrix3d& world_from_object, const Eigen::Vector3d& extent);

// Whether the segment from `a` to `b` (world) passes through the box's
// interior: VISIBLE FROM's line of sight is blocked by it. Touching the surface
// does not block.
bool SegmentCrossesBox(const OrientedBox& box, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace lsds
