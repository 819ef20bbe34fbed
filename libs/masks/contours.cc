#include "libs/masks/contours.h"

#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace lsds::masks {

namespace {

Polygon PiecePolygon(const std::vector<cv::Point>& contour, int left, int top) {
  std::vector<cv::Point> distinct;
  for (const cv::Point& p : contour) {
    if (std::find(distinct.begin(), distinct.end(), p) == distinct.end())
      distinct.push_back(p);
    if (distinct.size() >= 3) break;
  }
  Polygon polygon;
  if (distinct.size() < 3) {
    // A pixel or a straight 1-pixel line: its contour has no area, write its
    // pixel-edge rectangle.
    const cv::Rect r = cv::boundingRect(contour);
    const double x0 = left + r.x, y0 = top + r.y, x1 = x0 + r.width,
                 y1 = y0 + r.height;
    polygon = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    return polygon;
  }
  polygon.reserve(contour.size());
  for (const cv::Point& p : contour)
    polygon.emplace_back(left + p.x + 0.5, top + p.y + 0.5);
  return polygon;
}

}  // namespace

MaskPolygons ExtractPolygons(const BoxMask& mask) {
  MaskPolygons out;
  if (mask.empty()) return out;
  // A background border so that pieces touching the box edge are traced like
  // the others.
  cv::Mat padded;
  cv::copyMakeBorder(mask.mask, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(padded,
                   contours,
                   hierarchy,
                   cv::RETR_CCOMP,
                   cv::CHAIN_APPROX_SIMPLE,
                   cv::Point(-1, -1));
  std::vector<std::pair<double, Polygon>> pieces;
  for (size_t i = 0; i < contours.size(); ++i) {
    if (hierarchy[i][3] >= 0) {  // a hole inside an outer boundary
      ++out.holes;
      continue;
    }
    const cv::Rect r = cv::boundingRect(contours[i]);
    const double size =
        std::abs(cv::contourArea(contours[i])) + r.width + r.height;
    pieces.emplace_back(size, PiecePolygon(contours[i], mask.left, mask.top));
  }
  std::stable_sort(
      pieces.begin(), pieces.end(), [](const auto& a, const auto& b) {
        return a.first > b.first;
      });
  for (auto& piece : pieces) out.pieces.push_back(std::move(piece.second));
  return out;
}

Polygon MergePieces(const std::vector<Polygon>& pieces) {
  if (pieces.empty()) return {};
  Polygon merged = pieces[0];
  for (size_t k = 1; k < pieces.size(); ++k) {
    const Polygon& next = pieces[k];
    size_t best_i = 0, best_j = 0;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < merged.size(); ++i) {
      for (size_t j = 0; j < next.size(); ++j) {
        const cv::Point2d d = merged[i] - next[j];
        const double d2 = d.dot(d);
        if (d2 < best) {
          best = d2;
          best_i = i;
          best_j = j;
        }
      }
    }
    // merged[0..i], next[j..], next[..j], next[j], merged[i..]: out along the
    // bridge, round the piece, back along the same bridge.
    Polygon joined(merged.begin(), merged.begin() + best_i + 1);
    for (size_t t = 0; t <= next.size(); ++t)
      joined.push_back(next[(best_j + t) % next.size()]);
    joined.insert(joined.end(), merged.begin() + best_i, merged.end());
    merged = std::move(joined);
  }
  return merged;
}

}  // namespace lsds::masks
