// The sRGB transfer function (IEC 61966-2-1), the one home of both directions
// and of the 8-bit encoding table: display images (libs/imaging), point-cloud
// colours (backproject) and imported PNGs (importers) all use it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace lsds {

// Encoded sRGB value of a linear value `v` in [0, 1].
inline double SrgbFromLinear(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

// Linear value of an encoded sRGB value `c` in [0, 1] (8-bit value / 255,
// 16-bit value / 65535).
inline float LinearFromSrgb(double c) {
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

inline float LinearFromSrgb8(uint8_t value) { return LinearFromSrgb(value / 255.0); }

// The 8-bit sRGB encoding of [0, 1] sampled at kSteps + 1 points: entry k is
// round(255 * SrgbFromLinear(k / kSteps)). Index it with
// int(v * kSteps + 0.5) for v in [0, 1]; every output is exact except within
// 1/kSteps of a rounding boundary (the curve's steepest slope is 12.92).
template <int kSteps>
const std::array<uint8_t, kSteps + 1>& Srgb8Table() {
  static const std::array<uint8_t, kSteps + 1> table = [] {
    std::array<uint8_t, kSteps + 1> t{};
    for (int k = 0; k <= kSteps; ++k) {
      const double e = SrgbFromLinear(static_cast<double>(k) / kSteps);
      t[k] = static_cast<uint8_t>(std::lround(std::clamp(e, 0.0, 1.0) * 255.0));
    }
    return t;
  }();
  return table;
}

}  // namespace lsds
