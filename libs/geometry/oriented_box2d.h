// 2D oriented (rotated) boxes in the image, and the minimum-area rectangle
// around a point set or an instance mask (docs/format.md, "Oriented boxes").
// The one home of the 2D OBB: object truth, the validator and the converters
// (DOTA, YOLO-OBB, tiles) all measure it here.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "libs/geometry/box2d.h"

namespace lsds {

// A rectangle in pixel-edge image coordinates (x right, y down; pixel (i, j)
// covers [i, i+1) x [j, j+1), as Box2d). Consecutive corners share an edge and
// run clockwise as seen on the image (y down). corners[0] is the heading
// corner when the object's heading is known (docs/format.md), else the corner
// with the smallest y, ties broken by the smallest x.
struct OrientedBox2d {
  std::array<Eigen::Vector2d, 4> corners;

  Eigen::Vector2d Center() const { return (corners[0] + corners[2]) / 2; }
  double Width() const { return (corners[1] - corners[0]).norm(); }   // corners 0 -> 1
  double Height() const { return (corners[2] - corners[1]).norm(); }  // corners 1 -> 2
  double Area() const { return Width() * Height(); }
  // Axis-aligned bounds of the four corners.
  Box2d Bounds() const;
  // True when `point` lies inside or within `tolerance` pixels of the edges.
  bool Contains(const Eigen::Vector2d& point, double tolerance = 0.0) const;
};

// The minimum-area rectangle enclosing `points` (rotating calipers over their
// convex hull, in double precision), corners ordered as OrientedBox2d says
// with no heading; nullopt for no points. Collinear points give a rectangle of
// zero height.
std::optional<OrientedBox2d> MinimumAreaRectangle(const std::vector<Eigen::Vector2d>& points);

// The minimum-area rectangle enclosing every pixel square of `id` inside `box`
// of a row-major id layer of `width` x `height` (the visible OBB of an
// instance); nullopt when no pixel of `box` holds `id`.
std::optional<OrientedBox2d> MaskOrientedBox(
    const uint32_t* ids, int width, int height, uint32_t id, const Box2d& box);

// `box` cut to `region` (an image or a tile): `box` itself when its corners
// are inside `region`, else the minimum-area rectangle of the polygon
// box ∩ region (Sutherland-Hodgman), which may reach slightly out of `region`
// again (callers that need every corner inside clamp them); its first corner
// is the one on the side of `box`'s first edge (WithHeadingCornerFirst with
// that edge's outward normal), so a heading order survives. nullopt when the
// intersection has no area.
std::optional<OrientedBox2d> ClippedTo(const OrientedBox2d& box, const Box2d& region);

// Reorders `box`'s corners (keeping them clockwise) so that corners[0] is the
// heading corner: of the two corners of the front edge (the edge whose outward
// normal makes the smallest angle with the image-plane heading
// `heading_in_image`), the one on the left when looking along the heading
// (docs/format.md). Unchanged when the heading has zero length.
OrientedBox2d WithHeadingCornerFirst(const OrientedBox2d& box,
                                     const Eigen::Vector2d& heading_in_image);

}  // namespace lsds
