// Decoders written from the reference algorithms (pycocotools maskApi.c
// rleFrString/rleDecode; CVAT's mask import), independent of lsds' encoders, so
// that round trips test the conventions themselves.
#pragma once

#include <cstdint>
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
  for (size_t i = 0;
       i < column_major.size() && i < static_cast<size_t>(height) * width;
       ++i) {
    mask.at<uint8_t>(static_cast<int>(i % height),
                     static_cast<int>(i / height)) = column_major[i];
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
  while (std::getline(in, token, ','))
    counts.push_back(static_cast<uint32_t>(std::stoul(token)));
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

}  // namespace lsds::testing
