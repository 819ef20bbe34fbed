#include "libs/masks/coco_rle.h"

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
