// Decoders written from the reference algorithms (pycocotools maskApi.c
// rleFrString/rleDecode; CVAT's mask import), independent of lsds' encoders, so
// that round trips test the conventions themselves.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace lsds::testing {

// maskApi.c rleFrString: 6 bits per char from '0', bit 5 "more", sign bit 4 of
// the last chunk, counts after the third are deltas to the count two before.
inline std::vector<uint32_t> CocoCountsFromString(const std::string& s) {
  std::vector<uint32_t> counts;
  size_t p = 0;
  while (p < s.size()) {
    long x = 0;
    int k = 0;
    bool more = true;
    while (more) {
      const long c = static_cast<long>(s[p]) - 48;
      x |= (c & 0x1f) << (5 * k);
      more = (c & 0x20) != 0;
      ++p;
      ++k;
      if (!more && (c & 0x10)) x |= static_cast<long>(~0UL << (5 * k));
    }
    const size_t m = counts.size();
    if (m > 2) x += static_cast<long>(counts[m - 2]);
    counts.push_back(static_cast<uint32_t>(x));
  }
  return counts;
}

// maskApi.c rleDecode: runs alternate starting with 0, over the image in
// column-major order. Returns a row-major CV_8U image; `total` receives the sum
// of the counts (must be h * w).
inline cv::Mat CocoDecode(const std::vector<uint32_t>& counts,
                          int height,
                          int width,
                          int64_t* total) {
  std::vector<uint8_t> column_major;
  uint8_t v = 0;
  for (uint32_t c : counts) {
    column_major.insert(column_major.end(), c, v);
    v = !v;
  }
  *total = static_cast<int64_t>(column_major.size());
  cv::Mat mask = cv::Mat::zeros(height, width, CV_8U);
  for (size_t i = 0; i < column_major.size() && i < static_cast<size_t>(height) * width; ++i) {
    mask.at<uint8_t>(static_cast<int>(i % height), static_cast<int>(i / height)) = column_major[i];
  }
  return mask;
}

// CVAT mask: "a, b, c" runs alternating from background, row-major inside
// left/top/width/height.
inline cv::Mat CvatDecode(const std::string& rle,
                          int left,
                          int top,
                          int box_width,
                          int box_height,
                          int image_width,
                          int image_height,
                          int64_t* total) {
  std::vector<uint32_t> counts;
  std::stringstream in(rle);
  std::string token;
  while (std::getline(in, token, ',')) counts.push_back(static_cast<uint32_t>(std::stoul(token)));
  cv::Mat mask = cv::Mat::zeros(image_height, image_width, CV_8U);
  int64_t i = 0;
  uint8_t v = 0;
  for (uint32_t c : counts) {
    for (uint32_t k = 0; k < c; ++k, ++i) {
      if (v && i < int64_t{box_width} * box_height) {
        mask.at<uint8_t>(top + static_cast<int>(i / box_width),
                         left + static_cast<int>(i % box_width)) = 1;
      }
    }
    v = !v;
  }
  *total = i;
  return mask;
}

inline bool SameMask(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && cv::countNonZero(a != b) == 0;
}

// pycocotools' polygon rasterizer, ported line by line from
// cocodataset/cocoapi common/maskApi.c rleFrPoly (commit 8c9bcc3, 2020-02-20,
// the code pycocotools 2.0.x builds; frPyObjects calls it per polygon and
// unions the pieces with rleMerge). xy holds x0 y0 x1 y1 ...; returns the RLE
// counts (column-major, starting with background).
inline std::vector<uint32_t> CocoRleFrPoly(const std::vector<double>& xy, int h, int w) {
  const double scale = 5;
  const size_t k = xy.size() / 2;
  std::vector<int> x(k + 1), y(k + 1);
  for (size_t j = 0; j < k; j++) x[j] = (int)(scale * xy[j * 2 + 0] + .5);
  x[k] = x[0];
  for (size_t j = 0; j < k; j++) y[j] = (int)(scale * xy[j * 2 + 1] + .5);
  y[k] = y[0];
  std::vector<int> u, v;
  for (size_t j = 0; j < k; j++) {
    int xs = x[j], xe = x[j + 1], ys = y[j], ye = y[j + 1], dx, dy, t, d;
    int flip;
    double s;
    dx = std::abs(xe - xs);
    dy = std::abs(ys - ye);
    flip = (dx >= dy && xs > xe) || (dx < dy && ys > ye);
    if (flip) {
      t = xs;
      xs = xe;
      xe = t;
      t = ys;
      ys = ye;
      ye = t;
    }
    s = dx >= dy ? (double)(ye - ys) / dx : (double)(xe - xs) / dy;
    if (dx >= dy) {
      for (d = 0; d <= dx; d++) {
        t = flip ? dx - d : d;
        u.push_back(t + xs);
        v.push_back((int)(ys + s * t + .5));
      }
    } else {
      for (d = 0; d <= dy; d++) {
        t = flip ? dy - d : d;
        v.push_back(t + ys);
        u.push_back((int)(xs + s * t + .5));
      }
    }
  }
  // Points along the y-boundary, downsampled.
  std::vector<int> bx, by;
  for (size_t j = 1; j < u.size(); j++) {
    if (u[j] == u[j - 1]) continue;
    double xd = (double)(u[j] < u[j - 1] ? u[j] : u[j] - 1);
    xd = (xd + .5) / scale - .5;
    if (std::floor(xd) != xd || xd < 0 || xd > w - 1) continue;
    double yd = (double)(v[j] < v[j - 1] ? v[j] : v[j - 1]);
    yd = (yd + .5) / scale - .5;
    if (yd < 0)
      yd = 0;
    else if (yd > h)
      yd = h;
    yd = std::ceil(yd);
    bx.push_back((int)xd);
    by.push_back((int)yd);
  }
  std::vector<uint32_t> a;
  for (size_t j = 0; j < bx.size(); j++) a.push_back((uint32_t)(bx[j] * h + by[j]));
  a.push_back((uint32_t)(h * w));
  std::sort(a.begin(), a.end());
  uint32_t p = 0;
  for (uint32_t& t : a) {
    const uint32_t t0 = t;
    t -= p;
    p = t0;
  }
  std::vector<uint32_t> b;
  size_t j = 0;
  b.push_back(a[j++]);
  while (j < a.size()) {
    if (a[j] > 0) {
      b.push_back(a[j++]);
    } else {
      j++;
      if (j < a.size()) b.back() += a[j++];
    }
  }
  return b;
}

// frPyObjects + decode for a list of polygons: the union of each polygon's
// rleFrPoly mask (rleMerge with intersect = 0), as a row-major CV_8U image.
inline cv::Mat CocoPolygonsToMask(const std::vector<std::vector<double>>& polygons, int h, int w) {
  cv::Mat mask = cv::Mat::zeros(h, w, CV_8U);
  for (const std::vector<double>& xy : polygons) {
    int64_t total = 0;
    mask |= CocoDecode(CocoRleFrPoly(xy, h, w), h, w, &total);
  }
  return mask;
}

// Ultralytics' box of a polygon (ultralytics/utils/ops.py segment2box): the
// min/max of the points inside the image, in pixels.
inline cv::Rect2d UltralyticsSegmentToBox(const std::vector<cv::Point2d>& points,
                                          int width,
                                          int height) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const cv::Point2d& p : points) {
    if (p.x < 0 || p.y < 0 || p.x > width || p.y > height) continue;
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  return {x0, y0, x1 - x0, y1 - y0};
}

// Ultralytics' class rules for a detection dataset, as its loaders apply
// them: `names` of data.yaml must have the keys 0..n-1
// (ultralytics/nn/autobackend.py check_class_names: "n-class dataset requires
// class indices 0-(n-1)"), and every label's class must be below n
// (ultralytics/data/utils.py verify_image_label: "Label class exceeds dataset
// class count"). Returns the consumer's complaint, or "" when it accepts.
// `names` are the keys of data.yaml's names block; `label_classes` every class
// index of every label file.
inline std::string UltralyticsClassCheck(const std::vector<int>& names,
                                         const std::set<int>& label_classes) {
  const int n = static_cast<int>(names.size());
  for (int key : names) {
    if (key < 0 || key >= n)
      return std::to_string(n) + "-class dataset requires class indices 0-" +
             std::to_string(n - 1) + ", but you have invalid class index " + std::to_string(key);
  }
  if (!label_classes.empty() && *label_classes.rbegin() >= n)
    return "Label class " + std::to_string(*label_classes.rbegin()) +
           " exceeds dataset class count " + std::to_string(n);
  return "";
}

}  // namespace lsds::testing
