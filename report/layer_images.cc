#include "report/layer_images.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "report/draw.h"

namespace lsds::report {

namespace {

cv::Vec3b FlowColor(double dx, double dy, double max_magnitude) {
  const double magnitude = std::hypot(dx, dy);
  const double s = max_magnitude > 0 ? std::min(1.0, magnitude / max_magnitude) : 0.0;
  double hue = std::atan2(dy, dx) / (2 * M_PI);  // [-0.5, 0.5]
  if (hue < 0) hue += 1;
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(std::fmod(hue * 180.0, 180.0), s * 255, 255));
  cv::Mat bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr.at<cv::Vec3b>(0, 0);
}

}  // namespace

cv::Mat ColorizeIds(const exr::FlatImage& ids) {
  const std::vector<uint32_t>& v = ids.Get("id").uints;
  cv::Mat out(ids.height(), ids.width(), CV_8UC3);
  for (int y = 0; y < ids.height(); ++y) {
    for (int x = 0; x < ids.width(); ++x) {
      out.at<cv::Vec3b>(y, x) = IdColor(v[ids.Index(x, y)]);
    }
  }
  return out;
}

cv::Mat ColorizeDepth(const exr::FlatImage& depth, double* min, double* max) {
  const std::vector<float>& z = depth.Get("Z").floats;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (float v : z) {
    if (std::isfinite(v)) lo = std::min<double>(lo, v), hi = std::max<double>(hi, v);
  }
  if (!(lo <= hi)) lo = hi = 0;
  *min = lo, *max = hi;
  cv::Mat gray(depth.height(), depth.width(), CV_8U);
  cv::Mat invalid(depth.height(), depth.width(), CV_8U, cv::Scalar(0));
  const double span = hi > lo ? hi - lo : 1.0;
  for (int y = 0; y < depth.height(); ++y) {
    for (int x = 0; x < depth.width(); ++x) {
      const float v = z[depth.Index(x, y)];
      if (!std::isfinite(v)) {
        invalid.at<uchar>(y, x) = 1;
        gray.at<uchar>(y, x) = 0;
      } else {
        gray.at<uchar>(y, x) = static_cast<uchar>(std::lround(255.0 * (v - lo) / span));
      }
    }
  }
  cv::Mat out;
  cv::applyColorMap(gray, out, cv::COLORMAP_TURBO);
  out.setTo(cv::Scalar(48, 48, 48), invalid);
  return out;
}

cv::Mat DepthScaleBar(int width, int height) {
  cv::Mat gray(height, width, CV_8U);
  for (int x = 0; x < width; ++x) {
    gray.col(x).setTo(cv::Scalar(std::lround(255.0 * x / std::max(1, width - 1))));
  }
  cv::Mat out;
  cv::applyColorMap(gray, out, cv::COLORMAP_TURBO);
  return out;
}

cv::Mat ColorizeNormals(const exr::FlatImage& normals) {
  const std::vector<float>& nx = normals.Get("X").floats;
  const std::vector<float>& ny = normals.Get("Y").floats;
  const std::vector<float>& nz = normals.Get("Z").floats;
  cv::Mat out(normals.height(), normals.width(), CV_8UC3);
  auto byte = [](float v) {
    if (!std::isfinite(v)) return uchar{0};
    return static_cast<uchar>(std::lround(std::clamp((v + 1.0) / 2.0, 0.0, 1.0) * 255.0));
  };
  for (int y = 0; y < normals.height(); ++y) {
    for (int x = 0; x < normals.width(); ++x) {
      const size_t p = normals.Index(x, y);
      if (nx[p] == 0 && ny[p] == 0 && nz[p] == 0) {
        out.at<cv::Vec3b>(y, x) = cv::Vec3b(0, 0, 0);
      } else {
        out.at<cv::Vec3b>(y, x) = cv::Vec3b(byte(nz[p]), byte(ny[p]), byte(nx[p]));
      }
    }
  }
  return out;
}

cv::Mat ColorizeShadow(const exr::FlatImage& shadow) {
  const std::vector<float>& s = shadow.Get("Y").floats;
  cv::Mat out(shadow.height(), shadow.width(), CV_8UC3);
  for (int y = 0; y < shadow.height(); ++y) {
    for (int x = 0; x < shadow.width(); ++x) {
      const float v = s[shadow.Index(x, y)];
      const uchar g = std::isfinite(v)
                          ? static_cast<uchar>(std::lround(std::clamp(v, 0.f, 1.f) * 255.f))
                          : uchar{0};
      out.at<cv::Vec3b>(y, x) = cv::Vec3b(g, g, g);
    }
  }
  return out;
}

cv::Mat ColorizeMotion(const exr::FlatImage& motion, double* max_px, int64_t* invalid) {
  const std::vector<float>& mx = motion.Get("X").floats;
  const std::vector<float>& my = motion.Get("Y").floats;
  const int w = motion.width(), h = motion.height();
  // Screen-normalized: 0.5 + 0.5 * displacement / image size.
  auto dx = [&](size_t p) { return (mx[p] - 0.5) * 2.0 * w; };
  auto dy = [&](size_t p) { return (my[p] - 0.5) * 2.0 * h; };
  double largest = 0;
  *invalid = 0;
  for (size_t p = 0; p < mx.size(); ++p) {
    if (std::isfinite(mx[p]) && std::isfinite(my[p])) {
      largest = std::max(largest, std::hypot(dx(p), dy(p)));
    } else {
      ++*invalid;
    }
  }
  *max_px = largest;
  // Hue per pixel through one HSV image (cvtColor), not pixel by pixel.
  cv::Mat hsv(h, w, CV_8UC3);
  cv::Mat bad(h, w, CV_8U, cv::Scalar(0));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t p = motion.Index(x, y);
      if (!(std::isfinite(mx[p]) && std::isfinite(my[p]))) {
        bad.at<uchar>(y, x) = 1;
        hsv.at<cv::Vec3b>(y, x) = cv::Vec3b(0, 0, 0);
        continue;
      }
      const double ddx = dx(p), ddy = dy(p);
      double hue = std::atan2(ddy, ddx) / (2 * M_PI);
      if (hue < 0) hue += 1;
      const double s = largest > 0 ? std::min(1.0, std::hypot(ddx, ddy) / largest) : 0.0;
      hsv.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>(static_cast<int>(hue * 180.0) % 180),
                                          static_cast<uchar>(std::lround(s * 255)),
                                          255);
    }
  }
  cv::Mat out;
  cv::cvtColor(hsv, out, cv::COLOR_HSV2BGR);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!bad.at<uchar>(y, x)) continue;
      const bool dark = ((x / 4) + (y / 4)) % 2 == 0;
      out.at<cv::Vec3b>(y, x) = dark ? cv::Vec3b(90, 90, 90) : cv::Vec3b(150, 150, 150);
    }
  }
  return out;
}

cv::Mat FlowWheel(int size) {
  cv::Mat out(size, size, CV_8UC3, cv::Scalar(255, 255, 255));
  const double r = size / 2.0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double dx = x + 0.5 - r, dy = y + 0.5 - r;
      if (std::hypot(dx, dy) <= r) out.at<cv::Vec3b>(y, x) = FlowColor(dx, dy, r);
    }
  }
  return out;
}

}  // namespace lsds::report
