#include "libs/geometry/oriented_box2d.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace lsds {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; collinear points dropped. Counter-clockwise in a
// y-up frame, which is clockwise on the image (y down).
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  size_t k = 0;
  for (const Eigen::Vector2d& p : points) {
    while (k >= 2 && Cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && Cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Puts the corner with the smallest y (ties: smallest x) first and makes the
// order clockwise on the image (positive signed area with y down).
OrientedBox2d Canonical(std::array<Eigen::Vector2d, 4> c) {
  double area2 = 0;
  for (int i = 0; i < 4; ++i)
    area2 += c[i].x() * c[(i + 1) % 4].y() - c[(i + 1) % 4].x() * c[i].y();
  if (area2 < 0) std::swap(c[1], c[3]);
  int first = 0;
  for (int i = 1; i < 4; ++i) {
    if (c[i].y() < c[first].y() || (c[i].y() == c[first].y() && c[i].x() < c[first].x())) first = i;
  }
  OrientedBox2d box;
  for (int i = 0; i < 4; ++i) box.corners[i] = c[(first + i) % 4];
  return box;
}

}  // namespace

Box2d OrientedBox2d::Bounds() const {
  Box2d b{corners[0].x(), corners[0].y(), corners[0].x(), corners[0].y()};
  for (const Eigen::Vector2d& c : corners) {
    b.x0 = std::min(b.x0, c.x());
    b.y0 = std::min(b.y0, c.y());
    b.x1 = std::max(b.x1, c.x());
    b.y1 = std::max(b.y1, c.y());
  }
  return b;
}

bool OrientedBox2d::Contains(const Eigen::Vector2d& point, double tolerance) const {
  // Inside when the point lies within both slabs of the rectangle. A side of
  // zero length (the box of collinear points) has no slab: the point must then
  // lie on the line of the other side (or on the point, when both are zero).
  const Eigen::Vector2d offset = point - corners[0];
  const std::array<Eigen::Vector2d, 2> sides = {corners[1] - corners[0], corners[3] - corners[0]};
  for (int k = 0; k < 2; ++k) {
    const double length = sides[k].norm();
    if (length > 0) {
      const double along = offset.dot(sides[k]) / length;
      if (along < -tolerance || along > length + tolerance) return false;
      continue;
    }
    const Eigen::Vector2d& other = sides[1 - k];
    const double other_length = other.norm();
    const double across =
        other_length > 0 ? std::abs(offset.x() * other.y() - offset.y() * other.x()) / other_length
                         : offset.norm();
    if (across > tolerance) return false;
  }
  return true;
}

std::optional<OrientedBox2d> MinimumAreaRectangle(const std::vector<Eigen::Vector2d>& points) {
  if (points.empty()) return std::nullopt;
  const std::vector<Eigen::Vector2d> hull = ConvexHull(points);
  if (hull.size() == 1) return Canonical({hull[0], hull[0], hull[0], hull[0]});
  // The minimum-area rectangle has a side on a hull edge (Freeman & Shapira
  // 1975): try every edge. Hulls of masks have few vertices, so the quadratic
  // scan costs less than calipers' bookkeeping.
  double best_area = std::numeric_limits<double>::infinity();
  std::array<Eigen::Vector2d, 4> best = {hull[0], hull[0], hull[0], hull[0]};
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d edge = hull[(i + 1) % hull.size()] - hull[i];
    if (edge.norm() == 0) continue;
    const Eigen::Vector2d u = edge / edge.norm();
    const Eigen::Vector2d v(-u.y(), u.x());
    double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
    for (const Eigen::Vector2d& p : hull) {
      const double a = (p - hull[i]).dot(u), b = (p - hull[i]).dot(v);
      u0 = std::min(u0, a), u1 = std::max(u1, a), v0 = std::min(v0, b), v1 = std::max(v1, b);
    }
    const double area = (u1 - u0) * (v1 - v0);
    if (area < best_area) {
      best_area = area;
      best = {hull[i] + u0 * u + v0 * v,
              hull[i] + u1 * u + v0 * v,
              hull[i] + u1 * u + v1 * v,
              hull[i] + u0 * u + v1 * v};
    }
  }
  return Canonical(best);
}

std::optional<OrientedBox2d> MaskOrientedBox(
    const uint32_t* ids, int width, int height, uint32_t id, const Box2d& box) {
  // The hull of a set of pixel squares is the hull of the outer corners of
  // each row's first and last pixel.
  const Box2d clipped = box.ClippedTo(width, height);
  const int x0 = static_cast<int>(std::floor(clipped.x0)),
            x1 = static_cast<int>(std::ceil(clipped.x1));
  const int y0 = static_cast<int>(std::floor(clipped.y0)),
            y1 = static_cast<int>(std::ceil(clipped.y1));
  std::vector<Eigen::Vector2d> corners;
  for (int y = y0; y < y1; ++y) {
    const uint32_t* row = ids + static_cast<size_t>(y) * width;
    int first = -1, last = -1;
    for (int x = x0; x < x1; ++x) {
      if (row[x] != id) continue;
      if (first < 0) first = x;
      last = x;
    }
    if (first < 0) continue;
    corners.insert(corners.end(),
                   {Eigen::Vector2d(first, y),
                    Eigen::Vector2d(first, y + 1),
                    Eigen::Vector2d(last + 1, y),
                    Eigen::Vector2d(last + 1, y + 1)});
  }
  return MinimumAreaRectangle(corners);
}

std::optional<OrientedBox2d> ClippedTo(const OrientedBox2d& box, const Box2d& region) {
  const bool inside = std::all_of(box.corners.begin(), box.corners.end(), [&](const auto& c) {
    return c.x() >= region.x0 && c.x() <= region.x1 && c.y() >= region.y0 && c.y() <= region.y1;
  });
  if (inside) return box;
  // Sutherland-Hodgman against the four half-planes of `region`; `along`
  // gives a point's signed distance inside one of them.
  std::vector<Eigen::Vector2d> polygon(box.corners.begin(), box.corners.end());
  const std::array<std::function<double(const Eigen::Vector2d&)>, 4> inside_by = {
      [&](const Eigen::Vector2d& p) { return p.x() - region.x0; },
      [&](const Eigen::Vector2d& p) { return region.x1 - p.x(); },
      [&](const Eigen::Vector2d& p) { return p.y() - region.y0; },
      [&](const Eigen::Vector2d& p) { return region.y1 - p.y(); }};
  for (const auto& along : inside_by) {
    std::vector<Eigen::Vector2d> out;
    for (size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d& a = polygon[i];
      const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
      const double da = along(a), db = along(b);
      if (da >= 0) out.push_back(a);
      if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    polygon = std::move(out);
    if (polygon.empty()) return std::nullopt;
  }
  std::optional<OrientedBox2d> clipped = MinimumAreaRectangle(polygon);
  if (!clipped || clipped->Area() <= 0) return std::nullopt;
  const Eigen::Vector2d front = (box.corners[0] + box.corners[1]) / 2 - box.Center();
  return WithHeadingCornerFirst(*clipped, front);
}

OrientedBox2d WithHeadingCornerFirst(const OrientedBox2d& box,
                                     const Eigen::Vector2d& heading_in_image) {
  if (heading_in_image.norm() == 0) return box;
  // The front edge is the one whose outward normal points most along the
  // heading. The corners run clockwise on the image, so looking along the
  // heading an edge's first corner is on its left (facing +x with y down, the
  // left is -y: the edge from the top-right to the bottom-right corner).
  const Eigen::Vector2d center = box.Center();
  int front = 0;
  double best = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d mid = (box.corners[i] + box.corners[(i + 1) % 4]) / 2 - center;
    const double along = mid.norm() > 0 ? mid.normalized().dot(heading_in_image) : 0.0;
    if (along > best) best = along, front = i;
  }
  OrientedBox2d out;
  for (int i = 0; i < 4; ++i) out.corners[i] = box.corners[(front + i) % 4];
  return out;
}

}  // namespace lsds
