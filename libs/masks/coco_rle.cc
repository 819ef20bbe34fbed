#include "libs/masks/coco_rle.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace lsds::masks {

std::vector<uint32_t> CocoRleCounts(const BoxMask& mask) {
  const int64_t h = mask.image_height;
  std::vector<uint32_t> counts;
  // Column-major: runs walk down each column, then on to the top of the next
  // one. Everything outside the box is background, so only the box columns need
  // looking at.
  int64_t run = 0;     // length of the current run
  bool value = false;  // value of the current run; the first run is background
  auto push = [&](bool v, int64_t n) {
    if (n == 0) return;
    if (v != value) {
      counts.push_back(static_cast<uint32_t>(run));
      run = 0;
      value = v;
    }
    run += n;
  };
  if (mask.empty()) {
    push(false, h * mask.image_width);
  } else {
    push(false, h * mask.left);
    for (int c = 0; c < mask.width(); ++c) {
      push(false, mask.top);
      for (int r = 0; r < mask.height(); ++r) push(mask.mask.at<uint8_t>(r, c) != 0, 1);
      push(false, h - mask.top - mask.height());
    }
    push(false, h * (mask.image_width - mask.left - mask.width()));
  }
  counts.push_back(static_cast<uint32_t>(run));
  return counts;
}

std::string CocoRleToString(const std::vector<uint32_t>& counts) {
  std::string s;
  s.reserve(counts.size() * 2);
  for (size_t i = 0; i < counts.size(); ++i) {
    long x = static_cast<long>(counts[i]);
    if (i > 2) x -= static_cast<long>(counts[i - 2]);  // "i > 2", not ">= 2": as the COCO API does
    bool more = true;
    while (more) {
      char c = static_cast<char>(x & 0x1f);
      x >>= 5;  // arithmetic shift: negative differences end at -1
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      c += 48;
      s.push_back(c);
    }
  }
  return s;
}

}  // namespace lsds::masks

namespace lsds::masks {

bool CocoRleFromString(const std::string& text, std::vector<uint32_t>* counts) {
  counts->clear();
  size_t p = 0;
  while (p < text.size()) {
    int64_t x = 0;
    int k = 0;
    bool more = true;
    while (more) {
      if (p >= text.size() || k > 7) return false;  // ends mid-count, or no 32-bit count
      const int c = static_cast<unsigned char>(text[p]) - 48;
      if (c < 0 || c > 63) return false;
      x |= static_cast<int64_t>(c & 0x1f) << (5 * k);
      more = (c & 0x20) != 0;
      ++p;
      ++k;
      if (!more && (c & 0x10)) x |= static_cast<int64_t>(-1) * (int64_t{1} << (5 * k));
    }
    if (counts->size() > 2) x += (*counts)[counts->size() - 2];
    if (x < 0 || x > static_cast<int64_t>(UINT32_MAX)) return false;
    counts->push_back(static_cast<uint32_t>(x));
  }
  return true;
}

uint64_t CocoRleArea(const std::vector<uint32_t>& counts) {
  uint64_t area = 0;
  for (size_t j = 1; j < counts.size(); j += 2) area += counts[j];
  return area;
}

std::array<double, 4> CocoRleBox(const CocoRle& rle) {
  const uint64_t h = static_cast<uint64_t>(rle.height), w = static_cast<uint64_t>(rle.width);
  const size_t m = rle.counts.size() / 2 * 2;
  if (m == 0 || h == 0) return {0, 0, 0, 0};
  uint64_t xs = w, ys = h, xe = 0, ye = 0, cc = 0, xp = 0;
  for (size_t j = 0; j < m; ++j) {
    cc += rle.counts[j];
    const uint64_t t = cc - j % 2, y = t % h, x = (t - y) / h;
    if (j % 2 == 0) {
      xp = x;
    } else if (xp < x) {  // the run wraps to a next column: every row is covered
      ys = 0;
      ye = h - 1;
    }
    xs = std::min(xs, x);
    xe = std::max(xe, x);
    ys = std::min(ys, y);
    ye = std::max(ye, y);
  }
  return {static_cast<double>(xs),
          static_cast<double>(ys),
          static_cast<double>(xe - xs + 1),
          static_cast<double>(ye - ys + 1)};
}

namespace {

// Walks two RLEs of one image together, as rleIou and rleMerge do
// (maskApi.c:60-64, 86-91): `span(length, in_a, in_b)` for every stretch of
// pixels where neither mask changes value.
template <typename Span>
void ForEachSpan(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b, Span span) {
  uint64_t ca = a[0], cb = b[0], remaining = 1;
  size_t ia = 1, ib = 1;
  bool va = false, vb = false;
  while (remaining > 0) {
    const uint64_t c = std::min(ca, cb);
    if (c > 0) span(c, va, vb);
    ca -= c;
    if (!ca && ia < a.size()) ca = a[ia++], va = !va;
    cb -= c;
    if (!cb && ib < b.size()) cb = b[ib++], vb = !vb;
    remaining = ca + cb;
  }
}

}  // namespace

double CocoRleIou(const CocoRle& detection, const CocoRle& ground_truth, bool crowd) {
  if (detection.counts.empty() || ground_truth.counts.empty()) return 0;
  uint64_t intersection = 0, united = 0;
  ForEachSpan(detection.counts, ground_truth.counts, [&](uint64_t c, bool va, bool vb) {
    if (va || vb) united += c;
    if (va && vb) intersection += c;
  });
  if (intersection == 0) return 0;  // maskApi.c:92
  if (crowd) united = CocoRleArea(detection.counts);
  return static_cast<double>(intersection) / static_cast<double>(united);
}

namespace {

// maskApi's rounding, (int)(v + .5): towards zero after adding a half, which
// differs from lround for negative values; kept for bit-equal masks.
int MaskApiRound(double v) {
  return static_cast<int>(v + .5);  // NOLINT(bugprone-incorrect-roundings)
}

// The polygon upsampled by 5 and walked densely along every edge
// (maskApi.c:163-183): the boundary points u (x), v (y).
void DenseBoundary(const std::vector<double>& xy, std::vector<int>* u, std::vector<int>* v) {
  const double scale = 5;
  const size_t k = xy.size() / 2;
  std::vector<int> x(k + 1), y(k + 1);
  for (size_t j = 0; j < k; ++j) x[j] = MaskApiRound(scale * xy[j * 2]);
  for (size_t j = 0; j < k; ++j) y[j] = MaskApiRound(scale * xy[j * 2 + 1]);
  x[k] = x[0];
  y[k] = y[0];
  for (size_t j = 0; j < k; ++j) {
    int xs = x[j], xe = x[j + 1], ys = y[j], ye = y[j + 1];
    const int dx = std::abs(xe - xs), dy = std::abs(ys - ye);
    const bool flip = (dx >= dy && xs > xe) || (dx < dy && ys > ye);
    if (flip) std::swap(xs, xe), std::swap(ys, ye);
    const double s =
        dx >= dy ? static_cast<double>(ye - ys) / dx : static_cast<double>(xe - xs) / dy;
    const int steps = dx >= dy ? dx : dy;
    for (int d = 0; d <= steps; ++d) {
      const int t = flip ? steps - d : d;
      if (dx >= dy) {
        u->push_back(t + xs);
        v->push_back(MaskApiRound(ys + s * t));
      } else {
        v->push_back(t + ys);
        u->push_back(MaskApiRound(xs + s * t));
      }
    }
  }
}

// Where the boundary crosses a pixel column's centre, downsampled, as pixel
// indices x * height + y (maskApi.c:185-197).
std::vector<uint32_t> ColumnCrossings(const std::vector<int>& u,
                                      const std::vector<int>& v,
                                      int64_t height,
                                      int64_t width) {
  const double scale = 5;
  std::vector<uint32_t> a;
  for (size_t j = 1; j < u.size(); ++j) {
    if (u[j] == u[j - 1]) continue;
    double xd = static_cast<double>(u[j] < u[j - 1] ? u[j] : u[j] - 1);
    xd = (xd + .5) / scale - .5;
    if (std::floor(xd) != xd || xd < 0 || xd > static_cast<double>(width - 1)) continue;
    double yd = static_cast<double>(v[j] < v[j - 1] ? v[j] : v[j - 1]);
    yd = std::ceil(std::clamp((yd + .5) / scale - .5, 0.0, static_cast<double>(height)));
    a.push_back(static_cast<uint32_t>(static_cast<int>(xd) * static_cast<int>(height) +
                                      static_cast<int>(yd)));
  }
  return a;
}

}  // namespace

CocoRle CocoRleFromPolygon(const std::vector<double>& xy, int64_t height, int64_t width) {
  std::vector<int> u, v;
  DenseBoundary(xy, &u, &v);
  std::vector<uint32_t> a = ColumnCrossings(u, v, height, width);
  // The crossings sorted become run lengths; zero-length runs fold into the
  // next (maskApi.c:196-204).
  a.push_back(static_cast<uint32_t>(height * width));
  std::sort(a.begin(), a.end());
  uint32_t previous = 0;
  for (uint32_t& value : a) {
    const uint32_t t = value;
    value -= previous;
    previous = t;
  }
  CocoRle rle{height, width, {}};
  size_t j = 0;
  rle.counts.push_back(a[j++]);
  while (j < a.size()) {
    if (a[j] > 0) {
      rle.counts.push_back(a[j++]);
    } else {
      ++j;
      if (j < a.size()) rle.counts.back() += a[j++];
    }
  }
  return rle;
}

CocoRle CocoRleUnion(const std::vector<CocoRle>& masks) {
  if (masks.empty()) return {};
  CocoRle merged = masks[0];
  for (size_t i = 1; i < masks.size(); ++i) {
    if (masks[i].counts.empty()) continue;
    if (merged.counts.empty()) {
      merged.counts = masks[i].counts;
      continue;
    }
    // A run ends where the union's value changes (maskApi.c:58-66).
    std::vector<uint32_t> out;
    uint64_t run = 0;
    bool value = false;  // the first run is background
    ForEachSpan(merged.counts, masks[i].counts, [&](uint64_t c, bool va, bool vb) {
      if ((va || vb) != value) {
        out.push_back(static_cast<uint32_t>(run));
        run = 0;
        value = !value;
      }
      run += c;
    });
    out.push_back(static_cast<uint32_t>(run));
    merged.counts = std::move(out);
  }
  return merged;
}

}  // namespace lsds::masks
