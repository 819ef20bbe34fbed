// The pinhole camera model of the collection format (docs/format.md, "Camera
// model").
//
// Camera frame: OpenCV convention, x right, y down, z forward (the optical
// axis). Image coordinates are continuous pixel-edge coordinates: pixel (i, j)
// covers [i, i+1) x [j, j+1), so its centre is (i + 0.5, j + 0.5) and a centred
// principal point is (width / 2, height / 2).
//   u = fx * x / z + cx,  v = fy * y / z + cy
#pragma once

#include <string>

#include <Eigen/Core>

namespace lsds {

struct PinholeCamera {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0;  // focal lengths in pixels
  double cx = 0, cy = 0;  // principal point in pixel-edge coordinates

  // Square pixels, centred principal point, horizontal field of view in
  // degrees.
  static PinholeCamera FromHorizontalFov(int width, int height, double hfov_deg);

  double HorizontalFovDeg() const;
  double VerticalFovDeg() const;

  // Pixel coordinates of a point in the camera frame (z > 0 expected).
  Eigen::Vector2d ImageFromCam(const Eigen::Vector3d& point_in_cam) const {
    return {fx * point_in_cam.x() / point_in_cam.z() + cx,
            fy * point_in_cam.y() / point_in_cam.z() + cy};
  }
  // The ray through a pixel position, scaled so that z == 1 (multiply by planar
  // depth to get the point).
  Eigen::Vector3d CamFromImage(const Eigen::Vector2d& pixel) const {
    return {(pixel.x() - cx) / fx, (pixel.y() - cy) / fy, 1.0};
  }
  // The ray through the centre of pixel (i, j), z == 1.
  Eigen::Vector3d RayThroughPixelCenter(int i, int j) const {
    return CamFromImage({i + 0.5, j + 0.5});
  }
  // The `worldToNDC` convention of our EXR headers (docs/format.md): x_ndc =
  // 2u/width - 1, y_ndc = 2v/height - 1 (y down), z_ndc = 1/z, after division
  // by w = z.
  Eigen::Matrix4d NdcFromCam() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    m(0, 0) = 2 * fx / width;
    m(0, 2) = 2 * cx / width - 1;
    m(1, 1) = 2 * fy / height;
    m(1, 2) = 2 * cy / height - 1;
    m(2, 3) = 1;
    m(3, 2) = 1;
    return m;
  }
  bool operator==(const PinholeCamera& other) const {
    return width == other.width && height == other.height && fx == other.fx && fy == other.fy &&
           cx == other.cx && cy == other.cy;
  }
};

// Planar depth is measured along the optical axis (z); perspective depth along
// the ray (distance from the camera centre). For the ray r =
// CamFromImage(pixel) with r.z == 1: perspective = planar * |r|.
inline double PerspectiveFromPlanarDepth(const PinholeCamera& camera,
                                         const Eigen::Vector2d& pixel,
                                         double planar) {
  return planar * camera.CamFromImage(pixel).norm();
}
inline double PlanarFromPerspectiveDepth(const PinholeCamera& camera,
                                         const Eigen::Vector2d& pixel,
                                         double perspective) {
  return perspective / camera.CamFromImage(pixel).norm();
}

// The point in the camera frame seen at `pixel` with the given depth of either
// kind.
enum class DepthKind { kPlanar, kPerspective };
inline Eigen::Vector3d UnprojectDepth(const PinholeCamera& camera,
                                      const Eigen::Vector2d& pixel,
                                      double depth,
                                      DepthKind kind) {
  const Eigen::Vector3d ray = camera.CamFromImage(pixel);
  return kind == DepthKind::kPlanar ? Eigen::Vector3d(ray * depth)
                                    : Eigen::Vector3d(ray * (depth / ray.norm()));
}

const char* DepthKindName(DepthKind kind);  // "planar" | "perspective"
bool ParseDepthKind(const std::string& name, DepthKind* kind);

}  // namespace lsds
