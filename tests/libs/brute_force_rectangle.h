// A reference for the minimum-area rectangle, independent of the code under
// test: the smallest enclosing rectangle over all angles in [0, 90) degrees
// in steps of `step_deg`, an upper bound of the true minimum.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace lsds::testing {

inline double BruteForceMinimumArea(const std::vector<Eigen::Vector2d>& points,
                                    double step_deg = 0.01) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k * step_deg < 90.0; ++k) {
    const double angle = k * step_deg * M_PI / 180.0;
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle)), v(-std::sin(angle), std::cos(angle));
    double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
    for (const Eigen::Vector2d& p : points) {
      u0 = std::min(u0, p.dot(u)), u1 = std::max(u1, p.dot(u));
      v0 = std::min(v0, p.dot(v)), v1 = std::max(v1, p.dot(v));
    }
    best = std::min(best, (u1 - u0) * (v1 - v0));
  }
  return best;
}

}  // namespace lsds::testing
