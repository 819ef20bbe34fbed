#include "libs/imaging/image_codecs.h"

#include "libs/imaging/image_codecs_abi.h"
#include "libs/util/error.h"
#include "libs/util/plugin.h"

namespace lsds::imaging {

namespace {

// The plug-in's table, opened once per process on first use (thread-safe static
// initialisation). A failure is not cached: the next call retries and throws the same error.
const ImageCodecsTable& Codecs() {
  static const ImageCodecsTable* const table = [] {
    using Entry = const ImageCodecsTable* (*)();
    const auto entry =
        reinterpret_cast<Entry>(LoadPluginSymbol(kImageCodecsPlugin, kImageCodecsEntry));
    const ImageCodecsTable* loaded = entry();
    if (loaded == nullptr || loaded->abi_version != kImageCodecsAbiVersion) {
      throw Error(std::string("the plug-in ") + kImageCodecsPlugin + " has ABI version " +
                  (loaded ? std::to_string(loaded->abi_version) : "none") + ", lsds needs " +
                  std::to_string(kImageCodecsAbiVersion) + ": reinstall lsds");
    }
    return loaded;
  }();
  return *table;
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
