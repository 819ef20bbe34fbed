#include "bundles/mixed_map.h"

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

#include "libs/imaging/image_codecs.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::bundle {

std::vector<uint8_t> MixedMapBgr(const PixelMaps& maps, int width, int height) {
  if (maps.mixed.size() != static_cast<size_t>(width) * height) {
    throw Error("mixed map: pixel maps do not match the image size");
  }
  std::vector<uint8_t> image(static_cast<size_t>(width) * height * 3);
  for (size_t p = 0; p < maps.mixed.size(); ++p) {
    uint8_t* bgr = &image[3 * p];
    if (maps.mixed[p]) {
      // Purity 1 -> yellow, 0.5 -> red, 0 -> magenta: impurity reads as heat.
      const double impurity = std::clamp(1.0 - maps.purity[p], 0.0, 1.0);
      const double t = std::min(1.0, impurity * 2.0);
      const double u = std::max(0.0, impurity * 2.0 - 1.0);
      bgr[0] = static_cast<uint8_t>(255 * u);
      bgr[1] = static_cast<uint8_t>(255 * (1 - t));
      bgr[2] = 255;
    } else {
      const uint32_t id = maps.majority_instance[p];
      if (id == 0) {
        bgr[0] = bgr[1] = bgr[2] = 0;
      } else {
        // A dim, stable colour per instance so that objects stay recognisable.
        const uint32_t h = id * 2654435761u;
        bgr[0] = static_cast<uint8_t>(40 + (h & 63));
        bgr[1] = static_cast<uint8_t>(40 + ((h >> 8) & 63));
        bgr[2] = static_cast<uint8_t>(40 + ((h >> 16) & 63));
      }
    }
  }
  return image;
}

void WriteMixedMapPng(const std::filesystem::path& path,
                      const PixelMaps& maps,
                      int width,
                      int height) {
  if (maps.mixed.size() != static_cast<size_t>(width) * height) {
    throw Error("mixed map: pixel maps do not match the image size", Location(path.string()));
  }
  std::vector<uint8_t> bgr = MixedMapBgr(maps, width, height);
  const cv::Mat image(height, width, CV_8UC3, bgr.data());
  std::vector<uchar> png;
  if (!imaging::ImEncode(".png", image, png))
    throw Error("cannot encode PNG", Location(path.string()));
  WriteFileAtomic(path, std::string(png.begin(), png.end()));
}

}  // namespace lsds::bundle
