// SplitMix64 (Steele, Lea and Flood 2014), the one home of the project's
// seeded mixing: every seeded draw (noise, planner streams, Perlin
// permutations, split assignment) goes through these two functions, so "same
// seed, same bytes" rests on one definition.
#pragma once

#include <cstdint>

namespace lsds {

// The SplitMix64 finalizer: a bijective 64-bit mix with full avalanche.
inline uint64_t Mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// The golden-ratio increment of the SplitMix64 sequence.
inline constexpr uint64_t kSplitMixGamma = 0x9E3779B97F4A7C15ULL;

// The next value of the SplitMix64 sequence whose state is `*state`.
inline uint64_t SplitMix64Next(uint64_t* state) { return Mix64(*state += kSplitMixGamma); }

// The value after `x` in the sequence, as a pure function of `x`.
inline uint64_t SplitMix64(uint64_t x) { return Mix64(x + kSplitMixGamma); }

// Two values into one seed: the generator's per-object, per-pixel and
// per-sample streams, and so part of the documented sample-position rule
// (docs/format.md "Pixel bundles").
inline uint64_t HashCombine(uint64_t a, uint64_t b) { return SplitMix64(a ^ SplitMix64(b)); }

}  // namespace lsds
