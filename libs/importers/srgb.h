// 8-bit display colour (sRGB) of other simulators' PNGs back to the linear
// values of the rgb layer (IEC 61966-2-1 decoding).
#pragma once

#include <cmath>
#include <cstdint>

namespace lsds::import {

// `c` in [0, 1] (8-bit value / 255, 16-bit value / 65535).
inline float LinearFromSrgb(double c) {
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

inline float LinearFromSrgb8(uint8_t value) { return LinearFromSrgb(value / 255.0); }

}  // namespace lsds::import
