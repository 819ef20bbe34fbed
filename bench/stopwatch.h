// The benchmarks' clock: wall seconds since a point in time.
#pragma once

#include <chrono>

namespace lsds::bench {

using Clock = std::chrono::steady_clock;

inline double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

}  // namespace lsds::bench
