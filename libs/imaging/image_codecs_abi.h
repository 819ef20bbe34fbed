// The boundary between lsds and its image-codecs plug-in (libs/imaging/image_codecs.h).
// One extern "C" entry point returns a table of function pointers, so only one symbol is looked
// up by name. Both sides are built in the same tree against the same libopencv_core and
// libstdc++, so cv::Mat and std::vector cross by reference, and a cv::Exception thrown by
// OpenCV inside the plug-in propagates to the caller as it would from a direct call.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace lsds::imaging {

// Raised whenever the table's layout or meaning changes; the loader refuses any other value.
constexpr int kImageCodecsAbiVersion = 1;

struct ImageCodecsTable {
  int abi_version;
  void (*read)(const std::string& path, int flags, cv::Mat& image);
  void (*decode)(const cv::Mat& buffer, int flags, cv::Mat& image);
  bool (*write)(const std::string& path, const cv::Mat& image, const std::vector<int>& params);
  bool (*encode)(const std::string& ext,
                 const cv::Mat& image,
                 std::vector<uchar>& buffer,
                 const std::vector<int>& params);
};

constexpr const char* kImageCodecsPlugin = "lsds_image_codecs.so";
constexpr const char* kImageCodecsEntry = "lsds_image_codecs_table";

}  // namespace lsds::imaging

// Defined by the plug-in; looked up with dlsym by kImageCodecsEntry.
extern "C" const lsds::imaging::ImageCodecsTable* lsds_image_codecs_table();
