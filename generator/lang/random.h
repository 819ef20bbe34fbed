// Deterministic, platform-independent random streams. std:: distributions are
// implementation defined, so the planner draws through these helpers only: the
// same seed gives the same plan on every compiler and machine.
#pragma once

#include <cstdint>

#include "libs/util/splitmix64.h"

namespace lsds {

// Mixes values into one 64-bit key (order matters).
inline uint64_t MixKey(uint64_t a, uint64_t b) {
  uint64_t state = a ^ (b * 0xD1B54A32D192ED03ull);
  SplitMix64Next(&state);
  return SplitMix64Next(&state);
}

// Stream tags: the world stream, one stream per frame, one per fired scene
// change.
enum class StreamTag : uint64_t {
  kWorld = 1,
  kFrame = 2,
  kChange = 3,
  kTerrain = 4,
  kCount = 5,         // frame counts of capture paths, one stream per path instance
  kFlight = 6,        // waypoints of a smooth flight, one stream per path instance
  kObjectFlight = 7,  // an object's path, one stream per (rule, leg)
  kRequire = 8,       // soft requirements: (frame, requirement)
  kQuota = 9,         // a quota's strata: one stream per quota
  kRedraw = 10        // redraw `attempt` of frame k: (frame, attempt)
};

class Rng {
 public:
  explicit Rng(uint64_t key) : state_(key) {}
  // The stream for (seed, tag, index): e.g. frame k's stream is Rng::For(seed,
  // kFrame, k).
  static Rng For(uint64_t seed, StreamTag tag, uint64_t index, uint64_t sub = 0) {
    return Rng(MixKey(MixKey(MixKey(seed, static_cast<uint64_t>(tag)), index), sub));
  }
  uint64_t NextU64() { return SplitMix64Next(&state_); }
  // A key from the stream's position without drawing: for choices added to
  // the language later (a car's shape) that must leave every later draw, and so
  // every plan without them, as it was.
  uint64_t KeyHere(uint64_t purpose) const { return MixKey(state_, purpose); }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [lo, hi] (inclusive).
  int64_t UniformInt(int64_t lo, int64_t hi) {
    const uint64_t span = static_cast<uint64_t>(hi - lo) + 1;
    return lo + static_cast<int64_t>(span == 0 ? NextU64() : NextU64() % span);
  }

 private:
  uint64_t state_;
};

}  // namespace lsds
