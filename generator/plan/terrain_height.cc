#include "generator/plan/terrain_height.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <unordered_map>

#include "libs/util/splitmix64.h"

namespace lsds {
namespace {

using Permutation = std::array<int, 512>;

Permutation MakePermutation(uint64_t seed) {
  std::array<int, 256> p;
  for (int i = 0; i < 256; ++i) p[i] = i;
  uint64_t state = seed;
  for (int i = 255; i > 0; --i) {  // Fisher-Yates with an exact integer draw
    const int j = static_cast<int>(SplitMix64Next(&state) % static_cast<uint64_t>(i + 1));
    std::swap(p[i], p[j]);
  }
  Permutation out;
  for (int i = 0; i < 512; ++i) out[i] = p[i & 255];
  return out;
}

const Permutation& PermutationFor(uint64_t seed) {
  // A handful of terrains per process: cache so that meshing millions of
  // vertices stays cheap.
  static std::mutex mutex;
  static std::unordered_map<uint64_t, Permutation> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(seed);
  if (it == cache.end()) it = cache.emplace(seed, MakePermutation(seed)).first;
  return it->second;
}

double Fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double Lerp(double t, double a, double b) { return a + t * (b - a); }
double Grad(int hash, double x, double y) {
  // 8 gradient directions of equal length sqrt(2) scaled to keep the range
  // within [-1, 1].
  switch (hash & 7) {
    case 0:
      return x + y;
    case 1:
      return -x + y;
    case 2:
      return x - y;
    case 3:
      return -x - y;
    case 4:
      return x;
    case 5:
      return -x;
    case 6:
      return y;
    default:
      return -y;
  }
}

}  // namespace

double PerlinNoise2(uint64_t seed, double x, double y) {
  const Permutation& p = PermutationFor(seed);
  const double fx = std::floor(x), fy = std::floor(y);
  const int xi = static_cast<int>(static_cast<int64_t>(fx) & 255);
  const int yi = static_cast<int>(static_cast<int64_t>(fy) & 255);
  x -= fx;
  y -= fy;
  const double u = Fade(x), v = Fade(y);
  const int a = p[xi] + yi, b = p[xi + 1] + yi;
  const double value = Lerp(v,
                            Lerp(u, Grad(p[a], x, y), Grad(p[b], x - 1, y)),
                            Lerp(u, Grad(p[a + 1], x, y - 1), Grad(p[b + 1], x - 1, y - 1)));
  return std::max(-1.0, std::min(1.0, value));
}

double TerrainHeight(const PlannedTerrain& terrain, double x, double y) {
  if (!terrain.present || terrain.perlin_amplitude == 0.0) return 0.0;
  return terrain.perlin_amplitude * PerlinNoise2(terrain.perlin_seed,
                                                 terrain.perlin_frequency * x,
                                                 terrain.perlin_frequency * y);
}

std::optional<Eigen::Vector3d> IntersectTerrain(const PlannedTerrain& terrain,
                                                const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& direction,
                                                double max_range) {
  const Eigen::Vector3d d = direction.normalized();
  auto above = [&](double t) {
    const Eigen::Vector3d p = origin + t * d;
    return p.z() - TerrainHeight(terrain, p.x(), p.y());
  };
  if (!terrain.present || terrain.perlin_amplitude == 0) {
    if (!(d.z() < 0) || origin.z() <= 0) return std::nullopt;  // z = 0 plane
    const double t = -origin.z() / d.z();
    if (t > max_range) return std::nullopt;
    return origin + t * d;
  }
  if (above(0) <= 0) return std::nullopt;  // starts under the ground
  const double step = std::max(0.05, 0.1 / std::max(terrain.perlin_frequency, 1e-6));
  double t0 = 0;
  for (double t1 = step; t0 < max_range; t0 = t1, t1 += step) {
    t1 = std::min(t1, max_range);
    if (above(t1) > 0) continue;
    double lo = t0, hi = t1;  // above at lo, under at hi
    while (hi - lo > 1e-3) {
      const double mid = 0.5 * (lo + hi);
      (above(mid) > 0 ? lo : hi) = mid;
    }
    return origin + hi * d;
  }
  return std::nullopt;
}

}  // namespace lsds
