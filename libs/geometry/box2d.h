// Axis-aligned 2D boxes in continuous pixel-edge coordinates: a box covering
// only pixel (0, 0) is x0 = 0, y0 = 0, x1 = 1, y1 = 1 (COCO's rule).
#pragma once

#include <algorithm>

namespace lsds {

struct Box2d {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  double area() const { return std::max(0.0, width()) * std::max(0.0, height()); }
  bool empty() const { return !(x1 > x0 && y1 > y0); }
  bool Contains(const Box2d& other, double tolerance = 0.0) const {
    return other.x0 >= x0 - tolerance && other.y0 >= y0 - tolerance && other.x1 <= x1 + tolerance &&
           other.y1 <= y1 + tolerance;
  }
  Box2d ClippedTo(double width, double height) const {
    return {std::clamp(x0, 0.0, width),
            std::clamp(y0, 0.0, height),
            std::clamp(x1, 0.0, width),
            std::clamp(y1, 0.0, height)};
  }
  bool operator==(const Box2d& o) const {
    return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1;
  }
};

}  // namespace lsds
