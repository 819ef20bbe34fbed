// What the import fixtures share: the 8-bit sRGB encoding simulators write
// their colour PNGs with (IEC 61966-2-1), the inverse of the importers'
// LinearFromSrgb8 up to rounding.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lsds::testing {

inline uint8_t Srgb8(float linear) {
  const double c = std::clamp(static_cast<double>(linear), 0.0, 1.0);
  const double s =
      c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
  return static_cast<uint8_t>(std::lround(s * 255));
}

}  // namespace lsds::testing
