#include "libs/masks/contours.h"

#include <algorithm>
#include <limits>
#include <map>

#include <opencv2/imgproc.hpp>

namespace lsds::masks {

namespace {

// Directed pixel-edge steps, clockwise on screen (y down) with the piece on
// the right: 0 right, 1 down, 2 left, 3 up.
const int kDx[4] = {1, 0, -1, 0};
const int kDy[4] = {0, 1, 0, -1};

// The boundary loops of a binary CV_8U image (with a background border) along
// pixel edges. Each foreground pixel side that faces background is one unit
// step; at a corner where two pixels touch only diagonally the walk turns
// left, into the other pixel, so that an 8-connected piece is one loop (it
// passes that corner twice, which rasterizers count twice and so cancel).
// Only corners are kept as vertices.
// One edge-walking loop over the mask (a tracer state machine).
// NOLINTNEXTLINE(readability-function-cognitive-complexity)
std::vector<std::vector<cv::Point>> TraceEdgeLoops(const cv::Mat& filled) {
  auto at = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < filled.cols && y < filled.rows && filled.at<uint8_t>(y, x) != 0;
  };
  // Outgoing steps per grid corner, keyed by (y, x) for a deterministic start
  // at the top-left corner.
  std::map<std::pair<int, int>, std::vector<int>> out;
  for (int y = 0; y < filled.rows; ++y) {
    for (int x = 0; x < filled.cols; ++x) {
      if (!at(x, y)) continue;
      if (!at(x, y - 1)) out[{y, x}].push_back(0);
      if (!at(x + 1, y)) out[{y, x + 1}].push_back(1);
      if (!at(x, y + 1)) out[{y + 1, x + 1}].push_back(2);
      if (!at(x - 1, y)) out[{y + 1, x}].push_back(3);
    }
  }
  std::vector<std::vector<cv::Point>> loops;
  while (true) {
    auto start = out.begin();
    while (start != out.end() && start->second.empty()) ++start;
    if (start == out.end()) break;
    const cv::Point origin(start->first.second, start->first.first);
    int dir = start->second.front();
    start->second.erase(start->second.begin());
    std::vector<cv::Point> loop = {origin};
    cv::Point p = origin + cv::Point(kDx[dir], kDy[dir]);
    while (p != origin || !out[{p.y, p.x}].empty()) {
      std::vector<int>& next = out[{p.y, p.x}];
      if (next.empty()) break;  // cannot happen: every corner is balanced
      // Prefer a left turn, then straight on, then right.
      int chosen = -1;
      for (int turn : {3, 0, 1}) {
        const int d = (dir + turn) % 4;
        auto it = std::find(next.begin(), next.end(), d);
        if (it != next.end()) {
          chosen = d;
          next.erase(it);
          break;
        }
      }
      if (chosen < 0) break;
      if (chosen != dir) loop.push_back(p);
      dir = chosen;
      p += cv::Point(kDx[dir], kDy[dir]);
      if (p == origin && out[{p.y, p.x}].empty()) break;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

// The pixels of the piece a corner vertex stands for (padded coordinates):
// the only piece pixel at a convex corner, the one diagonal to the missing
// pixel at a concave corner. At a corner where two pixels touch only
// diagonally (passed twice), the pixel on the right of the arriving edge and
// then the one on the right of the leaving edge, so that every edge between
// two vertices runs along one row or column of boundary pixels.
std::vector<cv::Point> CornerPixels(const cv::Mat& filled,
                                    const cv::Point& previous,
                                    const cv::Point& corner,
                                    const cv::Point& next) {
  const cv::Point around[4] = {corner + cv::Point(-1, -1),
                               corner + cv::Point(0, -1),
                               corner + cv::Point(-1, 0),
                               corner};  // NW NE SW SE
  int inside = 0, last_in = 0, last_out = 0;
  for (int k = 0; k < 4; ++k) {
    if (filled.at<uint8_t>(around[k]) != 0) {
      ++inside;
      last_in = k;
    } else {
      last_out = k;
    }
  }
  if (inside == 1) return {around[last_in]};
  if (inside == 3) return {around[3 - last_out]};  // NW<->SE, NE<->SW
  // Arriving right, down, left or up, the piece is on the right: SW, NW, NE,
  // SE; leaving right, down, left or up: SE, SW, NW, NE.
  const cv::Point in = corner - previous, out = next - corner;
  const cv::Point arriving = in.x > 0   ? around[2]
                             : in.y > 0 ? around[0]
                             : in.x < 0 ? around[1]
                                        : around[3];
  const cv::Point leaving = out.x > 0   ? around[3]
                            : out.y > 0 ? around[2]
                            : out.x < 0 ? around[0]
                                        : around[1];
  return {arriving, leaving};
}

}  // namespace

MaskPolygons ExtractPolygons(const BoxMask& mask, PolygonVertices vertices) {
  MaskPolygons out;
  if (mask.empty()) return out;
  // A background border so that pieces touching the box edge are traced like
  // the others, and the outside is one 4-connected background region.
  cv::Mat padded;
  cv::copyMakeBorder(mask.mask, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  padded = padded != 0;
  cv::Mat labels;
  const int n = cv::connectedComponents(padded, labels, 8, CV_32S);
  std::vector<std::pair<int64_t, Polygon>> pieces;
  for (int k = 1; k < n; ++k) {
    cv::Mat piece = labels == k;  // 255 inside
    const int64_t pixels = cv::countNonZero(piece);
    // Holes: background not 4-connected to the border.
    cv::Mat outside = piece.clone();
    cv::floodFill(outside, cv::Point(0, 0), 128, nullptr, 0, 0, 4);
    const cv::Mat filled = outside != 128;
    const cv::Mat holes = filled & ~piece;
    out.hole_pixels += cv::countNonZero(holes);
    if (out.hole_pixels > 0) {
      cv::Mat hole_labels;
      out.holes += cv::connectedComponents(holes, hole_labels, 4, CV_32S) - 1;
    }
    for (const std::vector<cv::Point>& loop : TraceEdgeLoops(filled)) {
      Polygon polygon;
      polygon.reserve(loop.size());
      const size_t n = loop.size();
      for (size_t i = 0; i < n; ++i) {
        const cv::Point2d corner(mask.left + loop[i].x - 1, mask.top + loop[i].y - 1);
        if (vertices == PolygonVertices::kPixelCorners) {
          polygon.push_back(corner);
          continue;
        }
        for (const cv::Point& pixel :
             CornerPixels(filled, loop[(i + n - 1) % n], loop[i], loop[(i + 1) % n])) {
          // Towards the pixel: +inset when it lies right of (below) the
          // corner, -inset when left of (above) it.
          polygon.emplace_back(corner.x + (pixel.x == loop[i].x ? kCornerInset : -kCornerInset),
                               corner.y + (pixel.y == loop[i].y ? kCornerInset : -kCornerInset));
        }
      }
      pieces.emplace_back(pixels, std::move(polygon));
    }
  }
  std::stable_sort(
      pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
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
    for (size_t t = 0; t <= next.size(); ++t) joined.push_back(next[(best_j + t) % next.size()]);
    joined.insert(joined.end(), merged.begin() + best_i, merged.end());
    merged = std::move(joined);
  }
  return merged;
}

}  // namespace lsds::masks
