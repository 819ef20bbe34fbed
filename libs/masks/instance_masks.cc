#include "libs/masks/instance_masks.h"

#include <algorithm>

#include "libs/geometry/instance_mask.h"

namespace lsds::masks {

std::unordered_map<uint32_t, IdBounds> ComputeIdBounds(const uint32_t* ids, int width, int height) {
  std::unordered_map<uint32_t, IdBounds> bounds;
  for (const auto& [id, m] : MeasureInstanceMasks(ids, width, height)) {
    bounds[id] = {static_cast<int>(m.box.x0),
                  static_cast<int>(m.box.y0),
                  static_cast<int>(m.box.x1),
                  static_cast<int>(m.box.y1),
                  m.pixels};
  }
  return bounds;
}

BoxMask ExtractMask(
    const uint32_t* ids, int width, int height, uint32_t id, const IdBounds& bounds) {
  BoxMask out;
  out.image_width = width;
  out.image_height = height;
  if (bounds.count == 0) return out;
  out.left = bounds.x0;
  out.top = bounds.y0;
  out.mask = cv::Mat::zeros(bounds.y1 - bounds.y0, bounds.x1 - bounds.x0, CV_8U);
  for (int y = bounds.y0; y < bounds.y1; ++y) {
    const uint32_t* row = ids + static_cast<size_t>(y) * width;
    uint8_t* dst = out.mask.ptr<uint8_t>(y - bounds.y0);
    for (int x = bounds.x0; x < bounds.x1; ++x) {
      if (row[x] == id) {
        dst[x - bounds.x0] = 1;
        ++out.pixel_count;
      }
    }
  }
  return out;
}

cv::Mat ToFullImage(const BoxMask& mask) {
  cv::Mat full = cv::Mat::zeros(mask.image_height, mask.image_width, CV_8U);
  if (!mask.empty()) {
    mask.mask.copyTo(full(cv::Rect(mask.left, mask.top, mask.width(), mask.height())));
  }
  return full;
}

}  // namespace lsds::masks
