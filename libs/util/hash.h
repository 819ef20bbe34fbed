// 64-bit mixing used to derive independent seeds (splitmix64 finalizer). The
// generator's noise, object shapes and sub-pixel sample positions all hash
// through it, so it is part of the documented sample-position rule
// (docs/format.md "Pixel bundles").
#pragma once

#include <cstdint>

namespace lsds {

inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

inline uint64_t HashCombine(uint64_t a, uint64_t b) { return SplitMix64(a ^ SplitMix64(b)); }

}  // namespace lsds
