// Per-instance binary masks cut from an instance id layer, each inside its
// tight pixel box.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <opencv2/core.hpp>

namespace lsds::masks {

// A binary mask (CV_8U, 1 inside, 0 outside) of `width` x `height` pixels whose
// pixel (0, 0) is image pixel (left, top). The box is tight: every row and
// column holds a 1 (unless empty).
struct BoxMask {
  int left = 0, top = 0;
  cv::Mat mask;             // rows = height, cols = width
  int64_t pixel_count = 0;  // number of 1s
  int image_width = 0, image_height = 0;

  int width() const { return mask.cols; }
  int height() const { return mask.rows; }
  bool empty() const { return pixel_count == 0; }
};

// Tight bounds and pixel counts of every id != 0 of a row-major id image, in
// one pass (MeasureInstanceMasks, libs/geometry/instance_mask.h, in integers).
struct IdBounds {
  int x0, y0, x1, y1;  // pixel-edge: pixels x0..x1-1, y0..y1-1
  int64_t count;
};
std::unordered_map<uint32_t, IdBounds> ComputeIdBounds(const uint32_t* ids, int width, int height);

// The mask of `id` inside `bounds` (from ComputeIdBounds); an empty BoxMask
// when bounds.count == 0.
BoxMask ExtractMask(
    const uint32_t* ids, int width, int height, uint32_t id, const IdBounds& bounds);

// Expands a box mask into a full-image CV_8U mask (for tests and polygons
// across the image).
cv::Mat ToFullImage(const BoxMask& mask);

}  // namespace lsds::masks
