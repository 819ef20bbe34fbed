// The bounding box of a mask: the one definition of an id's tight pixel box
// and pixel count in an id layer. Object truth (libs/collection/object_truth.h),
// the mask converters (libs/masks) and the validator all measure masks here.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "libs/geometry/box2d.h"

namespace lsds {

// The pixels of one id in an id layer.
struct InstanceMask {
  int64_t pixels = 0;
  Box2d box;  // tight, pixel-edge: [x0, y0, x1, y1) of the pixels
};

// One pass over a row-major id layer of `width` x `height`: the mask of every
// non-zero id. 0 is background.
std::unordered_map<uint32_t, InstanceMask> MeasureInstanceMasks(const uint32_t* ids,
                                                                int width,
                                                                int height);
inline std::unordered_map<uint32_t, InstanceMask> MeasureInstanceMasks(
    const std::vector<uint32_t>& ids, int width, int height) {
  return MeasureInstanceMasks(ids.data(), width, height);
}

}  // namespace lsds
