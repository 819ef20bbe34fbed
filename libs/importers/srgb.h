// 8-bit display colour (sRGB) of other simulators' PNGs back to the linear
// values of the rgb layer (IEC 61966-2-1 decoding).
#pragma once

#include <cmath>
#include <cstdint>

namespace lsds::import {

inline float LinearFromSrgb8(uint8_t value) {
  const double c = value / 255.0;
  return static_cast<float>(c <= 0.04045 ? c / 12.92
                                         : std::pow((c + 0.055) / 1.055, 2.4));
}

}  // namespace lsds::import
