// 8-bit palette (indexed) PNGs as index images: Kubric writes its
// segmentation this way (index = object, the palette only colours it), and
// OpenCV would expand the palette to colours. Through libpng.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace lsds::import {

struct IndexImage {
  int width = 0, height = 0;
  std::vector<uint8_t> index;  // row-major, top row first
};

// Reads the palette indices of an indexed PNG (or the values of an 8-bit
// greyscale one); throws lsds::Error naming the file otherwise.
IndexImage ReadIndexedPng(const std::filesystem::path& path);

// Writes an indexed PNG with `palette` (RGB triplets, one per index used).
void WriteIndexedPng(const std::filesystem::path& path,
                     const IndexImage& image,
                     const std::vector<uint8_t>& palette_rgb);

}  // namespace lsds::import
