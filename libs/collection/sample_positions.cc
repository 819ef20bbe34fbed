#include "libs/collection/sample_positions.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "libs/util/error.h"
#include "libs/util/splitmix64.h"

namespace lsds {
namespace {

int SamplesPerAxis(int spp) {
  return static_cast<int>(std::lround(std::sqrt(static_cast<double>(spp))));
}

double Uniform(uint64_t h) { return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0); }

}  // namespace

void CheckSamplerSettings(const SamplerSettings& s) {
  const int n = SamplesPerAxis(s.spp);
  if (s.spp < 1 || s.spp > 256 || n * n != s.spp) {
    throw Error("--spp " + std::to_string(s.spp) + ": samples per pixel must be a square number " +
                "(1, 4, 9, 16, ...) up to 256, for stratified n x n sampling");
  }
  if (!(s.jitter >= 0 && s.jitter <= 1)) throw Error("--jitter must be in [0, 1]");
}

FrameSampler::FrameSampler(const SamplerSettings& settings, int64_t frame)
    : per_axis_(SamplesPerAxis(settings.spp)),
      jitter_(settings.jitter),
      frame_seed_(HashCombine(settings.seed, static_cast<uint64_t>(frame))),
      sample_hashes_(static_cast<size_t>(std::max(settings.spp, 0))) {
  for (size_t k = 0; k < sample_hashes_.size(); ++k) sample_hashes_[k] = SplitMix64(k);
}

void FrameSampler::PixelSamples(int x, int y, Eigen::Vector2d* out) const {
  // Locals, not members: the stores to `out` may alias them.
  const int n = per_axis_;
  const double jitter = jitter_;
  const uint64_t* sample_hashes = sample_hashes_.data();
  // HashCombine(frame seed, pixel), then HashCombine(pixel seed, k) with k's
  // half of the mix precomputed: the same bits as the rule's definition.
  const uint64_t pixel_seed = HashCombine(frame_seed_, (static_cast<uint64_t>(y) << 32) | x);
  int nearest = 0;
  double nearest_d2 = 1e9;
  for (int cy = 0, k = 0; cy < n; ++cy) {
    for (int cx = 0; cx < n; ++cx, ++k) {
      double jx = 0, jy = 0;
      if (jitter > 0) {
        const uint64_t h = SplitMix64(pixel_seed ^ sample_hashes[k]);
        jx = jitter * (Uniform(h) - 0.5);
        jy = jitter * (Uniform(HashCombine(h, 1)) - 0.5);
      }
      const double ox = (cx + 0.5 + jx) / n, oy = (cy + 0.5 + jy) / n;
      out[k] = Eigen::Vector2d(x + ox, y + oy);
      const double d2 = (ox - 0.5) * (ox - 0.5) + (oy - 0.5) * (oy - 0.5);
      if (d2 < nearest_d2) {
        nearest_d2 = d2;
        nearest = k;
      }
    }
  }
  // The nearest sample becomes the exact centre and moves to the front; the
  // others keep cell order.
  const Eigen::Vector2d first(x + 0.5, y + 0.5);
  for (int k = nearest; k > 0; --k) out[k] = out[k - 1];
  out[0] = first;
}

void PixelSamples(const SamplerSettings& s, int64_t frame, int x, int y, Eigen::Vector2d* out) {
  FrameSampler(s, frame).PixelSamples(x, y, out);
}

}  // namespace lsds
