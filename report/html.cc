#include "report/html.h"

#include <vector>

#include "libs/imaging/image_codecs.h"
#include "libs/util/error.h"

namespace lsds::report {

std::string Base64(const std::string& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) |
                       (uint32_t(uint8_t(bytes[i + 1])) << 8) | uint32_t(uint8_t(bytes[i + 2]));
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) | (uint32_t(uint8_t(bytes[i + 1])) << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

std::string ImageDataUri(const cv::Mat& bgr, bool jpeg, int jpeg_quality) {
  std::vector<uchar> encoded;
  const std::vector<int> params = jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, jpeg_quality}
                                       : std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 6};
  if (!imaging::ImEncode(jpeg ? ".jpg" : ".png", bgr, encoded, params)) {
    throw Error("report: cannot encode an image");
  }
  return std::string(jpeg ? "data:image/jpeg;base64," : "data:image/png;base64,") +
         Base64(std::string(encoded.begin(), encoded.end()));
}

}  // namespace lsds::report
