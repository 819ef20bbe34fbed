#include "libs/geometry/instance_mask.h"

#include <algorithm>

namespace lsds {

std::unordered_map<uint32_t, InstanceMask> MeasureInstanceMasks(const uint32_t* ids,
                                                                int width,
                                                                int height) {
  struct Extent {
    int64_t pixels = 0;
    int x0, y0, x1, y1;  // pixel-edge
  };
  std::unordered_map<uint32_t, Extent> extents;
  for (int y = 0; y < height; ++y) {
    const uint32_t* row = ids + static_cast<size_t>(y) * width;
    int x = 0;
    while (x < width) {
      // Ids come in runs along a row: one lookup per run, not per pixel.
      const uint32_t id = row[x];
      int end = x + 1;
      while (end < width && row[end] == id) ++end;
      if (id != 0) {
        auto [it, inserted] = extents.try_emplace(id, Extent{0, x, y, end, y + 1});
        Extent& e = it->second;
        if (!inserted) {
          e.x0 = std::min(e.x0, x);
          e.x1 = std::max(e.x1, end);
          e.y1 = y + 1;  // rows are visited in order
        }
        e.pixels += end - x;
      }
      x = end;
    }
  }
  std::unordered_map<uint32_t, InstanceMask> masks;
  masks.reserve(extents.size());
  for (const auto& [id, e] : extents) {
    masks[id] = {e.pixels, Box2d{double(e.x0), double(e.y0), double(e.x1), double(e.y1)}};
  }
  return masks;
}

}  // namespace lsds
