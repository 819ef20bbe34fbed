#include "libs/masks/cvat_rle.h"

namespace lsds::masks {

std::vector<uint32_t> CvatRleCounts(const BoxMask& mask) {
  std::vector<uint32_t> counts;
  uint32_t run = 0;
  bool value = false;
  for (int r = 0; r < mask.height(); ++r) {
    const uint8_t* row = mask.mask.ptr<uint8_t>(r);
    for (int c = 0; c < mask.width(); ++c) {
      const bool v = row[c] != 0;
      if (v != value) {
        counts.push_back(run);
        run = 0;
        value = v;
      }
      ++run;
    }
  }
  counts.push_back(run);
  return counts;
}

std::string CvatRleToString(const std::vector<uint32_t>& counts) {
  std::string s;
  for (size_t i = 0; i < counts.size(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(counts[i]);
  }
  return s;
}

}  // namespace lsds::masks
