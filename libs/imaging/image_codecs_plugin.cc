// The image-codecs plug-in: forwards the four calls of libs/imaging/image_codecs.h to OpenCV's
// imgcodecs, and nothing else. It is built as a CMake MODULE, the only target of the product
// that links opencv_imgcodecs.
#include <opencv2/imgcodecs.hpp>

#include "libs/imaging/image_codecs_abi.h"

namespace {

void Read(const std::string& path, int flags, cv::Mat& image) { image = cv::imread(path, flags); }

void Decode(const cv::Mat& buffer, int flags, cv::Mat& image) {
  image = cv::imdecode(buffer, flags);
}

bool Write(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  return cv::imwrite(path, image, params);
}

bool Encode(const std::string& ext,
            const cv::Mat& image,
            std::vector<uchar>& buffer,
            const std::vector<int>& params) {
  return cv::imencode(ext, image, buffer, params);
}

const lsds::imaging::ImageCodecsTable kTable = {
    lsds::imaging::kImageCodecsAbiVersion, Read, Decode, Write, Encode};

}  // namespace

extern "C" __attribute__((visibility("default"))) const lsds::imaging::ImageCodecsTable*
lsds_image_codecs_table() {
  return &kTable;
}
