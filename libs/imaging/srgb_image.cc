#include "libs/imaging/srgb_image.h"

#include <array>
#include <cmath>

#include "libs/imaging/image_codecs.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/srgb.h"

namespace lsds::imaging {

namespace {

// Fine enough that every 8-bit output is exact except within 1/kSteps of a
// rounding boundary.
constexpr int kSteps = 1 << 16;

}  // namespace

bool ParseToneMap(const std::string& name, ToneMap* tonemap) {
  if (name == "clamp") {
    *tonemap = ToneMap::kClamp;
  } else if (name == "reinhard") {
    *tonemap = ToneMap::kReinhard;
  } else if (name == "filmic") {
    *tonemap = ToneMap::kFilmic;
  } else {
    return false;
  }
  return true;
}

float ToneCurve(ToneMap tonemap, float v) {
  if (!(v > 0.f)) return 0.f;  // negatives and NaN
  if (tonemap == ToneMap::kReinhard) v = v / (1.f + v);
  if (tonemap == ToneMap::kFilmic) v = v * (2.51f * v + 0.03f) / (v * (2.43f * v + 0.59f) + 0.14f);
  return v < 1.f ? v : 1.f;
}

cv::Mat ToSrgb8(const exr::FlatImage& rgb, const DisplayOptions& options) {
  const std::array<uint8_t, kSteps + 1>& table = Srgb8Table<kSteps>();
  const float scale = static_cast<float>(std::exp2(options.exposure_ev));
  const float* channels[3] = {
      rgb.Get("B").floats.data(), rgb.Get("G").floats.data(), rgb.Get("R").floats.data()};
  cv::Mat out(rgb.height(), rgb.width(), CV_8UC3);
  for (int y = 0; y < rgb.height(); ++y) {
    uint8_t* dst = out.ptr<uint8_t>(y);
    const size_t row = static_cast<size_t>(y) * rgb.width();
    for (int x = 0; x < rgb.width(); ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = ToneCurve(options.tonemap, channels[c][row + x] * scale);
        // v >= 0 (a tone curve), so truncating v + 0.5 rounds half up, as intended.
        // NOLINTNEXTLINE(bugprone-incorrect-roundings)
        dst[3 * x + c] = table[static_cast<int>(v * kSteps + 0.5f)];
      }
    }
  }
  return out;
}

void WriteImage(const std::filesystem::path& path,
                const cv::Mat& bgr,
                const DisplayOptions& options) {
  std::vector<int> params;
  const std::string ext = path.extension().string();
  if (ext == ".jpg" || ext == ".jpeg") {
    params = {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality};
  } else {
    params = {cv::IMWRITE_PNG_COMPRESSION, options.png_compression};
  }
  bool ok = false;
  std::vector<uchar> encoded;
  try {
    ok = imaging::ImEncode(ext.empty() ? std::string(".png") : ext, bgr, encoded, params);
  } catch (const cv::Exception& e) {
    throw Error(std::string("cannot write image: ") + e.what(), Location(path.string()));
  }
  if (!ok) throw Error("cannot write image", Location(path.string()));
  // Through the one checked, atomic output path.
  WriteFileAtomic(path, std::string(encoded.begin(), encoded.end()));
}

}  // namespace lsds::imaging
