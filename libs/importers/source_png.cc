#include "libs/importers/source_png.h"

#include <opencv2/imgcodecs.hpp>

#include "libs/util/error.h"
#include "libs/util/srgb.h"

namespace lsds::import {

exr::FlatImage ReadSrgbLayer(const std::filesystem::path& path,
                             int width,
                             int height,
                             const std::string& size_source) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty() || image.cols != width || image.rows != height ||
      (image.depth() != CV_8U && image.depth() != CV_16U) || image.channels() < 3)
    throw Error("missing, unreadable or not a " + std::to_string(width) + "x" +
                    std::to_string(height) + " RGB(A) PNG (" + size_source + ")",
                Location(path.string()));
  const double scale = image.depth() == CV_8U ? 1 / 255.0 : 1 / 65535.0;
  const int channels = image.channels();
  exr::FlatImage rgb(width, height);
  float* channel[3] = {rgb.AddChannel("R", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("G", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("B", exr::PixelType::kHalf).floats.data()};
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < 3; ++c) {
        // OpenCV's order is B, G, R(, A).
        const int k = i * channels + (2 - c);
        const double v =
            image.depth() == CV_8U ? image.ptr<uint8_t>(j)[k] : image.ptr<uint16_t>(j)[k];
        channel[c][rgb.Index(i, j)] = LinearFromSrgb(v * scale);
      }
  return rgb;
}

cv::Mat ReadRgbaPng(const std::filesystem::path& path, int width, int height) {
  cv::Mat colours = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (colours.empty() || colours.type() != CV_8UC4 || colours.cols != width ||
      colours.rows != height)
    throw Error("missing, unreadable or not a " + std::to_string(width) + "x" +
                    std::to_string(height) + " 8-bit RGBA PNG",
                Location(path.string()));
  return colours;
}

std::string RgbaText(uint32_t rgba) {
  return "(" + std::to_string(rgba >> 24) + ", " + std::to_string((rgba >> 16) & 0xff) + ", " +
         std::to_string((rgba >> 8) & 0xff) + ", " + std::to_string(rgba & 0xff) + ")";
}

}  // namespace lsds::import
