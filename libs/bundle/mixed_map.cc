#include "libs/bundle/mixed_map.h"

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::bundle {

void WriteMixedMapPng(const std::filesystem::path& path,
                      const PixelMaps& maps,
                      int width,
                      int height) {
  if (maps.mixed.size() != static_cast<size_t>(width) * height) {
    throw Error("mixed map: pixel maps do not match the image size",
                Location(path.string()));
  }
  cv::Mat image(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t p = static_cast<size_t>(y) * width + x;
      cv::Vec3b& bgr = image.at<cv::Vec3b>(y, x);
      if (maps.mixed[p]) {
        // Purity 1 -> yellow, 0.5 -> red, 0 -> magenta: impurity reads as heat.
        const double impurity = std::clamp(1.0 - maps.purity[p], 0.0, 1.0);
        const double t = std::min(1.0, impurity * 2.0);
        const double u = std::max(0.0, impurity * 2.0 - 1.0);
        bgr = cv::Vec3b(static_cast<uchar>(255 * u),
                        static_cast<uchar>(255 * (1 - t)),
                        255);
      } else {
        const uint32_t id = maps.majority_instance[p];
        if (id == 0) {
          bgr = cv::Vec3b(0, 0, 0);
        } else {
          // A dim, stable colour per instance so that objects stay
          // recognisable.
          const uint32_t h = id * 2654435761u;
          bgr = cv::Vec3b(
              40 + (h & 63), 40 + ((h >> 8) & 63), 40 + ((h >> 16) & 63));
        }
      }
    }
  }
  std::vector<uchar> png;
  if (!cv::imencode(".png", image, png))
    throw Error("cannot encode PNG", Location(path.string()));
  WriteFileAtomic(path, std::string(png.begin(), png.end()));
}

}  // namespace lsds::bundle
