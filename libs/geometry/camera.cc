#include "libs/geometry/camera.h"

#include <cmath>

namespace lsds {

namespace {
constexpr double kPi = 3.14159265358979323846;
double Deg(double rad) { return rad * 180.0 / kPi; }
double Rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

PinholeCamera PinholeCamera::FromHorizontalFov(int width, int height, double hfov_deg) {
  PinholeCamera camera;
  camera.width = width;
  camera.height = height;
  camera.fx = camera.fy = 0.5 * width / std::tan(0.5 * Rad(hfov_deg));
  camera.cx = 0.5 * width;
  camera.cy = 0.5 * height;
  return camera;
}

double PinholeCamera::HorizontalFovDeg() const { return Deg(2.0 * std::atan(0.5 * width / fx)); }
double PinholeCamera::VerticalFovDeg() const { return Deg(2.0 * std::atan(0.5 * height / fy)); }

const char* DepthKindName(DepthKind kind) {
  return kind == DepthKind::kPlanar ? "planar" : "perspective";
}

bool ParseDepthKind(const std::string& name, DepthKind* kind) {
  if (name == "planar") {
    *kind = DepthKind::kPlanar;
  } else if (name == "perspective") {
    *kind = DepthKind::kPerspective;
  } else {
    return false;
  }
  return true;
}

}  // namespace lsds
