#include "libs/imaging/image_codecs.h"

#include "libs/imaging/image_codecs_abi.h"
#include "libs/util/plugin.h"

namespace lsds::imaging {

namespace {

const ImageCodecsTable& Codecs() {
  return PluginTable<ImageCodecsTable>(
      kImageCodecsPlugin, kImageCodecsEntry, kImageCodecsAbiVersion);
}

}  // namespace

cv::Mat ImRead(const std::string& path, int flags) {
  cv::Mat image;
  Codecs().read(path, flags, image);
  return image;
}

cv::Mat ImDecode(cv::InputArray buffer, int flags) {
  cv::Mat image;
  Codecs().decode(buffer.getMat(), flags, image);
  return image;
}

bool ImWrite(const std::string& path, cv::InputArray image, const std::vector<int>& params) {
  return Codecs().write(path, image.getMat(), params);
}

bool ImEncode(const std::string& ext,
              cv::InputArray image,
              std::vector<uchar>& buffer,
              const std::vector<int>& params) {
  return Codecs().encode(ext, image.getMat(), buffer, params);
}

}  // namespace lsds::imaging
