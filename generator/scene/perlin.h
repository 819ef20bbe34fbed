// Seeded gradient (Perlin) noise and its fractal sum, the source of terrain
// heights, rock shapes, material variation and clouds. Deterministic: the same
// seed gives the same field on every machine.
#pragma once

#include <array>
#include <cstdint>

namespace lsds::gen {

class Perlin {
 public:
  explicit Perlin(uint64_t seed = 0);

  // Noise in about [-1, 1]; 0 at integer lattice points.
  double Noise(double x, double y, double z) const;
  // The z = 0 slice, at half the cost: the 3D noise's own operations on the
  // four lattice corners of that slice (equal to Noise(x, y, 0.0) up to the
  // sign of a zero).
  double Noise(double x, double y) const;
  // A bound on the slope of Noise(x, y) per lattice unit. In a cell the noise
  // blends four corner terms g.(p - corner), whose gradients g have components
  // in {-1, 0, 1}: along x, the fade's slope (at most 30/16) times a corner
  // difference (at most 3), plus the blended g_x (at most 1), is at most 6.625
  // per axis, 9.37 in all. The largest slope measured is 2.75 (test
  // Perlin.TheSlopeOfThe2DNoiseIsBounded).
  static constexpr double kSlopeBound2D = 9.37;
  // Fractal Brownian motion: `octaves` octaves, each at twice the frequency and
  // half the amplitude, normalized to about [-1, 1].
  double Fbm(double x, double y, double z, int octaves) const;
  double Fbm(double x, double y, int octaves) const;

 private:
  std::array<uint8_t, 512> permutation_;
};

// A 64-bit mix of two values (splitmix64 finalizer); used to derive independent
// seeds.
uint64_t HashCombine(uint64_t a, uint64_t b);
uint64_t HashString(const char* text);

}  // namespace lsds::gen
