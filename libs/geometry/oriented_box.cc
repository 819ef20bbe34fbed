#include "libs/geometry/oriented_box.h"

#include <algorithm>
#include <vector>

namespace lsds {

std::array<Eigen::Vector3d, 8> OrientedBox::Corners() const {
  std::array<Eigen::Vector3d, 8> corners;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d sign((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0);
    corners[k] = center + world_from_box * sign.cwiseProduct(half_extents);
  }
  return corners;
}

bool OrientedBox::Contains(const Eigen::Vector3d& point_in_world, double tolerance) const {
  const Eigen::Vector3d local = world_from_box.transpose() * (point_in_world - center);
  return (local.cwiseAbs() - half_extents).maxCoeff() <= tolerance;
}

bool OrientedBox::Intersects(const OrientedBox& other) const {
  const Eigen::Matrix3d& a = world_from_box;
  const Eigen::Matrix3d& b = other.world_from_box;
  const Eigen::Vector3d d = other.center - center;
  std::vector<Eigen::Vector3d> axes;
  axes.reserve(15);  // 3 + 3 face normals, 9 edge cross products
  for (int i = 0; i < 3; ++i) axes.push_back(a.col(i));
  for (int i = 0; i < 3; ++i) axes.push_back(b.col(i));
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d axis = a.col(i).cross(b.col(j));
      if (axis.squaredNorm() > 1e-12) axes.push_back(axis.normalized());
    }
  }
  for (const Eigen::Vector3d& axis : axes) {
    double ra = 0, rb = 0;
    for (int i = 0; i < 3; ++i) {
      ra += half_extents[i] * std::abs(a.col(i).dot(axis));
      rb += other.half_extents[i] * std::abs(b.col(i).dot(axis));
    }
    if (std::abs(d.dot(axis)) >= ra + rb) return false;
  }
  return true;
}

std::vector<Eigen::Vector2d> ProjectedSilhouettePoints(const OrientedBox& box,
                                                       const PinholeCamera& camera,
                                                       const Rigid3d& cam_from_world,
                                                       double near) {
  const auto corners = box.Corners();
  std::array<Eigen::Vector3d, 8> in_cam;
  for (int k = 0; k < 8; ++k) in_cam[k] = cam_from_world * corners[k];
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < 8; ++k) {
    if (in_cam[k].z() >= near) points.push_back(camera.ImageFromCam(in_cam[k]));
    for (int bit = 0; bit < 3; ++bit) {  // each edge once: from k to k with one bit set
      if (k & (1 << bit)) continue;
      const Eigen::Vector3d& p = in_cam[k];
      const Eigen::Vector3d& q = in_cam[k | (1 << bit)];
      if ((p.z() < near) != (q.z() < near)) {
        const double t = (near - p.z()) / (q.z() - p.z());
        points.push_back(camera.ImageFromCam(p + t * (q - p)));
      }
    }
  }
  return points;
}

namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Andrew's monotone chain; counter-clockwise hull.
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && Cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i > 0; --i) {
    while (k >= lower && Cross(hull[k - 2], hull[k - 1], points[i - 1]) <= 0) --k;
    hull[k++] = points[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

double PolygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice_area = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * std::abs(twice_area);
}

// Sutherland-Hodgman against one half-plane: keep points with sign * (p[axis] -
// limit) <= 0.
std::vector<Eigen::Vector2d> ClipHalfPlane(const std::vector<Eigen::Vector2d>& polygon,
                                           int axis,
                                           double limit,
                                           double sign) {
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    const double da = sign * (a[axis] - limit), db = sign * (b[axis] - limit);
    if (da <= 0) out.push_back(a);
    if ((da < 0) != (db < 0) && da != 0 && db != 0) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

}  // namespace

std::optional<Box2d> ProjectedBounds(const OrientedBox& box,
                                     const PinholeCamera& camera,
                                     const Rigid3d& cam_from_world,
                                     double near) {
  const auto points = ProjectedSilhouettePoints(box, camera, cam_from_world, near);
  if (points.empty()) return std::nullopt;
  Box2d bounds{points[0].x(), points[0].y(), points[0].x(), points[0].y()};
  for (const auto& p : points) {
    bounds.x0 = std::min(bounds.x0, p.x());
    bounds.y0 = std::min(bounds.y0, p.y());
    bounds.x1 = std::max(bounds.x1, p.x());
    bounds.y1 = std::max(bounds.y1, p.y());
  }
  return bounds;
}

double InFrameFraction(const OrientedBox& box,
                       const PinholeCamera& camera,
                       const Rigid3d& cam_from_world,
                       double near) {
  const auto hull = ConvexHull(ProjectedSilhouettePoints(box, camera, cam_from_world, near));
  const double total = hull.size() >= 3 ? PolygonArea(hull) : 0.0;
  if (total <= 0) return 0.0;
  auto clipped = ClipHalfPlane(hull, 0, 0.0, -1.0);
  clipped = ClipHalfPlane(clipped, 0, camera.width, 1.0);
  clipped = ClipHalfPlane(clipped, 1, 0.0, -1.0);
  clipped = ClipHalfPlane(clipped, 1, camera.height, 1.0);
  return clipped.size() >= 3 ? std::min(1.0, PolygonArea(clipped) / total) : 0.0;
}

}  // namespace lsds
