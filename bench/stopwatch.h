// The benchmarks' clocks: wall seconds since a point in time, and CPU seconds
// (user + system) of this process and of its waited-for children.
#pragma once

#include <sys/resource.h>

#include <chrono>

namespace lsds::bench {

using Clock = std::chrono::steady_clock;

inline double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// User + system seconds of this process and of the children it has waited for
// (a child's time counts once it ended): a benchmark's cost on a loaded machine.
inline double CpuSeconds() {
  double total = 0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage usage{};
    getrusage(who, &usage);
    total += static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  }
  return total;
}

}  // namespace lsds::bench
