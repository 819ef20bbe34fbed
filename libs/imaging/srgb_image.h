// Scene-linear RGB (an EXR colour layer) to an 8-bit sRGB image for training
// and review tools.
#pragma once

#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"

namespace lsds::imaging {

enum class ToneMap { kClamp, kReinhard };
bool ParseToneMap(const std::string& name, ToneMap* tonemap);

struct DisplayOptions {
  double exposure_ev = 0;             // linear values are multiplied by 2^EV first
  ToneMap tonemap = ToneMap::kClamp;  // clamp: min(v, 1); reinhard: v / (1 + v)
  int jpeg_quality = 95;
  int png_compression = 1;  // zlib level: fast, the files are still lossless
};

// 8-bit BGR (OpenCV's order) of the R, G, B channels of `rgb`: v * 2^EV, tone
// mapped to [0, 1], encoded with the sRGB transfer function (IEC 61966-2-1) and
// rounded to the nearest of 0..255. NaN and negative values map to 0.
cv::Mat ToSrgb8(const exr::FlatImage& rgb, const DisplayOptions& options);

// Writes PNG or JPEG by the extension of `path` (not atomic by itself: callers
// write into a temporary output folder). Throws lsds::Error naming the file on
// failure.
void WriteImage(const std::filesystem::path& path,
                const cv::Mat& bgr,
                const DisplayOptions& options);

}  // namespace lsds::imaging
