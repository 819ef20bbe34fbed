// The PNGs other simulators write, read with OpenCV into lsds layers: the
// colour image (8- or 16-bit sRGB, alpha ignored) as the linear rgb layer,
// and colour-coded segmentation (RGBA) as packed colours. Errors name the
// file and say what was expected.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"

namespace lsds::import {

// The rgb layer (HALF R, G, B, linear) of an sRGB PNG that must be
// width x height; `size_source` says where that size comes from.
exr::FlatImage ReadSrgbLayer(const std::filesystem::path& path,
                             int width,
                             int height,
                             const std::string& size_source);

// A width x height 8-bit RGBA PNG (OpenCV's BGRA order).
cv::Mat ReadRgbaPng(const std::filesystem::path& path, int width, int height);

// 0xRRGGBBAA of an OpenCV BGRA pixel.
inline uint32_t PackedRgba(const cv::Vec4b& bgra) {
  return (uint32_t{bgra[2]} << 24) | (uint32_t{bgra[1]} << 16) | (uint32_t{bgra[0]} << 8) | bgra[3];
}
// "(r, g, b, a)", as Replicator's mappings and messages write colours.
std::string RgbaText(uint32_t rgba);

}  // namespace lsds::import
