// Scene-linear RGB (an EXR colour layer) to an 8-bit sRGB image for training
// and review tools.
#pragma once

#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"

namespace lsds::imaging {

// The tone curves of the 8-bit exports (docs/generator.md, "Tone curve"), the
// one home of them: linear exposed value v (1: the sensor's saturation, see
// frames[k].exposure) to a linear display value in [0, 1], before the sRGB
// encoding.
//   clamp:    min(v, 1)
//   reinhard: v / (1 + v)
//   filmic:   the ACES filmic fit of K. Narkowicz (2015),
//             v (2.51 v + 0.03) / (v (2.43 v + 0.59) + 0.14), clamped to
//             [0, 1]: a toe, a near-linear mid range (0.18 -> 0.27) and a
//             soft shoulder that reaches 1 at v = 7.24.
enum class ToneMap { kClamp, kReinhard, kFilmic };
// "clamp", "reinhard" or "filmic".
bool ParseToneMap(const std::string& name, ToneMap* tonemap);
float ToneCurve(ToneMap tonemap, float v);

struct DisplayOptions {
  double exposure_ev = 0;              // linear values are multiplied by 2^EV first
  ToneMap tonemap = ToneMap::kFilmic;  // the curve applied before the sRGB encoding
  int jpeg_quality = 95;
  int png_compression = 1;  // zlib level: fast, the files are still lossless
};

// 8-bit BGR (OpenCV's order) of the R, G, B channels of `rgb`: v * 2^EV, tone
// mapped to [0, 1] (ToneCurve), encoded with the sRGB transfer function (IEC 61966-2-1) and
// rounded to the nearest of 0..255. NaN and negative values map to 0.
cv::Mat ToSrgb8(const exr::FlatImage& rgb, const DisplayOptions& options);

// Writes PNG or JPEG by the extension of `path` (not atomic by itself: callers
// write into a temporary output folder). Throws lsds::Error naming the file on
// failure.
void WriteImage(const std::filesystem::path& path,
                const cv::Mat& bgr,
                const DisplayOptions& options);

}  // namespace lsds::imaging
