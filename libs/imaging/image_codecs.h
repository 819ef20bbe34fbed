// Image file codecs (PNG, JPEG, TIFF, ...): OpenCV's imgcodecs, loaded on first use.
//
// libopencv_imgcodecs pulls in GDAL and about 140 other shared libraries; linking it made every
// lsds process load them at start-up. These four calls forward to the plug-in
// lsds_image_codecs.so (libs/imaging/image_codecs_plugin.cc), the only thing that links
// imgcodecs, which is opened the first time one of them runs (libs/util/plugin.h says where it is
// looked for). Arguments, results and exceptions (cv::Exception) are those of cv::imread,
// cv::imdecode, cv::imwrite and cv::imencode, so every byte read or written is the same.
// When the plug-in cannot be found or opened they throw lsds::Error naming the paths tried.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>
// For the flag constants only (cv::IMREAD_*, cv::IMWRITE_*): nothing here links imgcodecs.
#include <opencv2/imgcodecs.hpp>

namespace lsds::imaging {

cv::Mat ImRead(const std::string& path, int flags = cv::IMREAD_COLOR);
cv::Mat ImDecode(cv::InputArray buffer, int flags);
bool ImWrite(const std::string& path,
             cv::InputArray image,
             const std::vector<int>& params = std::vector<int>());
bool ImEncode(const std::string& ext,
              cv::InputArray image,
              std::vector<uchar>& buffer,
              const std::vector<int>& params = std::vector<int>());

}  // namespace lsds::imaging
