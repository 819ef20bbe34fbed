// Counter-based random numbers: every draw is a pure function of (seed, field,
// frame, draw), so the same seed gives the same noise on every machine, in any
// order and for any subset of frames, without carrying generator state.
// std::normal_distribution is not used because its output is not specified by
// the standard (libstdc++ and libc++ differ); Box-Muller over our own uniforms
// is.
#pragma once

#include <cmath>
#include <cstdint>

#include "libs/util/splitmix64.h"

namespace lsds {

using ::lsds::Mix64;

inline uint64_t CounterHash(uint64_t seed, uint64_t field, uint64_t frame, uint64_t draw) {
  uint64_t h = Mix64(seed + kSplitMixGamma);
  h = Mix64(h ^ ((field + 1) * 0xD1B54A32D192ED03ULL));
  h = Mix64(h ^ ((frame + 1) * 0xABC98388FB8FAC03ULL));
  return Mix64(h ^ ((draw + 1) * 0x8CB92BA72F3D8DD7ULL));
}

// Uniform on the open interval (0, 1): 53 random bits, offset by half a step so
// 0 never occurs.
inline double Uniform01(uint64_t seed, uint64_t field, uint64_t frame, uint64_t draw) {
  return (static_cast<double>(CounterHash(seed, field, frame, draw) >> 11) + 0.5) *
         (1.0 / 9007199254740992.0);
}

// Standard normal by Box-Muller from draws 2k and 2k+1.
inline double StandardNormal(uint64_t seed, uint64_t field, uint64_t frame, uint64_t k = 0) {
  constexpr double kTwoPi = 6.283185307179586476925;
  const double u1 = Uniform01(seed, field, frame, 2 * k);
  const double u2 = Uniform01(seed, field, frame, 2 * k + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

}  // namespace lsds
