#include "generator/scene/perlin.h"

#include <cmath>
#include <string>

#include "libs/util/splitmix64.h"

namespace lsds::gen {
namespace {

// The noise is a tenth of a frame's time (docs/generator.md "Performance").
// An AVX2 clone, picked at load time, rounds with vroundsd and needs fewer
// moves; "avx2" does not enable FMA, so nothing is contracted and the clone
// returns the baseline's bits (tests/generator/scene_test.cc). clang 14 emits no
// definition for cloned member functions, so its builds (the sanitizer preset) take the baseline.
#if defined(__x86_64__) && !defined(__clang__)
#define LSDS_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define LSDS_AVX2_CLONE
#endif

double Fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double Lerp(double t, double a, double b) { return a + t * (b - a); }

double Grad(int hash, double x, double y, double z) {
  const int h = hash & 15;
  const double u = h < 8 ? x : y;
  const double v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
  return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

}  // namespace

uint64_t HashCombine(uint64_t a, uint64_t b) { return lsds::HashCombine(a, b); }

uint64_t HashString(const char* text) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (const char* c = text; *c; ++c) h = (h ^ static_cast<uint8_t>(*c)) * 1099511628211ull;
  return h;
}

Perlin::Perlin(uint64_t seed) {
  std::array<uint8_t, 256> p;
  for (int i = 0; i < 256; ++i) p[i] = static_cast<uint8_t>(i);
  uint64_t state = seed;
  for (int i = 255; i > 0; --i) {  // Fisher-Yates with a portable generator
    state = SplitMix64(state);
    const int j = static_cast<int>(state % static_cast<uint64_t>(i + 1));
    std::swap(p[i], p[j]);
  }
  for (int i = 0; i < 512; ++i) permutation_[i] = p[i & 255];
}

LSDS_AVX2_CLONE double Perlin::Noise(double x, double y, double z) const {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const int X = static_cast<int>(static_cast<int64_t>(fx) & 255);
  const int Y = static_cast<int>(static_cast<int64_t>(fy) & 255);
  const int Z = static_cast<int>(static_cast<int64_t>(fz) & 255);
  x -= fx;
  y -= fy;
  z -= fz;
  const double u = Fade(x), v = Fade(y), w = Fade(z);
  const auto& P = permutation_;
  const int A = P[X] + Y, AA = P[A] + Z, AB = P[A + 1] + Z;
  const int B = P[X + 1] + Y, BA = P[B] + Z, BB = P[B + 1] + Z;
  return Lerp(
      w,
      Lerp(v,
           Lerp(u, Grad(P[AA], x, y, z), Grad(P[BA], x - 1, y, z)),
           Lerp(u, Grad(P[AB], x, y - 1, z), Grad(P[BB], x - 1, y - 1, z))),
      Lerp(v,
           Lerp(u, Grad(P[AA + 1], x, y, z - 1), Grad(P[BA + 1], x - 1, y, z - 1)),
           Lerp(u, Grad(P[AB + 1], x, y - 1, z - 1), Grad(P[BB + 1], x - 1, y - 1, z - 1))));
}

LSDS_AVX2_CLONE double Perlin::Noise(double x, double y) const {
  const double fx = std::floor(x), fy = std::floor(y);
  const int X = static_cast<int>(static_cast<int64_t>(fx) & 255);
  const int Y = static_cast<int>(static_cast<int64_t>(fy) & 255);
  x -= fx;
  y -= fy;
  const double u = Fade(x), v = Fade(y);
  const auto& P = permutation_;
  const int A = P[X] + Y, AA = P[A], AB = P[A + 1];
  const int B = P[X + 1] + Y, BA = P[B], BB = P[B + 1];
  return Lerp(v,
              Lerp(u, Grad(P[AA], x, y, 0.0), Grad(P[BA], x - 1, y, 0.0)),
              Lerp(u, Grad(P[AB], x, y - 1, 0.0), Grad(P[BB], x - 1, y - 1, 0.0)));
}

double Perlin::Fbm(double x, double y, int octaves) const {
  double sum = 0, amplitude = 1, norm = 0;
  for (int i = 0; i < octaves; ++i) {
    sum += amplitude * Noise(x, y);
    norm += amplitude;
    amplitude *= 0.5;
    x *= 2;
    y *= 2;
  }
  return norm > 0 ? sum / norm : 0;
}

double Perlin::Fbm(double x, double y, double z, int octaves) const {
  double sum = 0, amplitude = 1, norm = 0;
  for (int i = 0; i < octaves; ++i) {
    sum += amplitude * Noise(x, y, z);
    norm += amplitude;
    amplitude *= 0.5;
    x *= 2;
    y *= 2;
    z *= 2;
  }
  return norm > 0 ? sum / norm : 0;
}

}  // namespace lsds::gen
