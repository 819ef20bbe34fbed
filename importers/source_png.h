// The PNGs other simulators write, read with OpenCV into lsds layers: the
// colour image (8- or 16-bit sRGB, alpha ignored) as the linear rgb layer,
// and colour-coded segmentation (RGBA) as packed colours. Errors name the
// file and say what was expected.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"

namespace lsds::import {

// What a PNG's IHDR chunk declares.
struct PngHeader {
  int64_t width = 0, height = 0;
  int bit_depth = 8;
  int colour_type = 0;  // 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
  int Samples() const;  // per pixel, as stored (palette: 1)
};

// The IHDR of `path`, from its first 33 bytes; nullopt when the file does not
// start with the PNG signature (another format: its decoder says so). Throws
// lsds::Error naming the file for a PNG whose IHDR is missing or malformed.
std::optional<PngHeader> ReadPngHeader(const std::filesystem::path& path);

// Refuses, before anything is decoded, a PNG whose header declares a size
// beyond the EXR readers' limits (exr::ReadLimits), more pixel bytes than its
// file could hold (deflate expands at most 1032:1), or a decoded image of
// `bytes_per_pixel` beyond the memory budget.
void CheckPngSize(const std::filesystem::path& path,
                  const PngHeader& header,
                  int64_t bytes_per_pixel);

// cv::imread within the limits: a PNG's header is read and checked first
// (CheckPngSize, at the decoded size of `flags`); OpenCV's own refusals
// (cv::Exception) become lsds::Error naming the file. An empty Mat when
// OpenCV cannot read it, as cv::imread.
cv::Mat ReadImage(const std::filesystem::path& path, int flags);

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
