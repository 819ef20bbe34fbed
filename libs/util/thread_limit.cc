#include "libs/util/thread_limit.h"

#include <cstddef>

#include <tbb/global_control.h>

namespace lsds {

struct ThreadLimit::Control {
  explicit Control(size_t threads)
      : control(tbb::global_control::max_allowed_parallelism, threads) {}
  tbb::global_control control;
};

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0) {
    control_ = std::make_unique<Control>(static_cast<size_t>(threads));
  }
}

ThreadLimit::~ThreadLimit() = default;

}  // namespace lsds
