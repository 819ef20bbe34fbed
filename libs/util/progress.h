// A progress line with rate and ETA on a terminal; silent in CI (CI=true),
// when stderr is not a TTY, or after Silence() (-q).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace lsds {

class Progress {
 public:
  Progress(std::string label, int64_t total, std::string unit = "frames");
  ~Progress();                 // finishes the line
  void Add(int64_t done = 1);  // thread-safe

  static bool Enabled();  // a terminal, not CI, and not silenced
  // -q of every command: no progress line for the rest of the process.
  static void Silence();

 private:
  void Draw(bool final);

  std::string label_;
  std::string unit_;
  int64_t total_;
  std::atomic<int64_t> done_{0};
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
};

}  // namespace lsds
