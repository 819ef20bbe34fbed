// The one cap on TBB's worker threads (--threads T of every command).
#pragma once

#include <memory>

namespace lsds {

// Caps TBB's worker threads at `threads` for its lifetime (0: no cap, every
// core). Nested limits keep the smallest, as TBB's global_control does.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Control;  // tbb::global_control, kept out of the header
  std::unique_ptr<Control> control_;
};

}  // namespace lsds
