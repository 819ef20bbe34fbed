// Lossless residuals of floats against a prediction, shared by the layouts that
// store them (worldposition `residual`, bundle `residual`; docs/format.md): the
// difference of the two bit patterns, modulo 2^32, with its sign folded into
// the lowest bit. A bijection of uint32, so a layout built on it is exact
// whatever the prediction; a good prediction makes the stored numbers small,
// and zip then finds long runs of zero high bytes.
#pragma once

#include <cstdint>
#include <cstring>

namespace lsds {

inline uint32_t FloatBits(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

inline float FloatFromBits(uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// ("zigzag": 0, -1, 1, -2, ... -> 0, 1, 2, 3, ...) so that a prediction a few
// ulps above the truth stores a small number, not one near 2^32.
inline uint32_t FoldedDifference(uint32_t truth_bits, uint32_t predicted_bits) {
  const uint32_t d = truth_bits - predicted_bits;  // modulo 2^32
  return (d << 1) ^ (0u - (d >> 31));
}

inline uint32_t UnfoldedSum(uint32_t predicted_bits, uint32_t folded) {
  const uint32_t d = (folded >> 1) ^ (0u - (folded & 1u));
  return predicted_bits + d;  // modulo 2^32
}

}  // namespace lsds
