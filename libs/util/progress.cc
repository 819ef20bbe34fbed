#include "libs/util/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace lsds {

namespace {

std::atomic<bool> silenced{false};

}  // namespace

void Progress::Silence() { silenced = true; }

bool Progress::Enabled() {
  if (silenced) return false;
  // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
  const char* ci = std::getenv("CI");
  if (ci != nullptr && std::strcmp(ci, "") != 0 && std::strcmp(ci, "0") != 0 &&
      std::strcmp(ci, "false") != 0) {
    return false;
  }
  return ::isatty(STDERR_FILENO) != 0;
}

Progress::Progress(std::string label, int64_t total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(Enabled()),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  if (enabled_) Draw(true);
}

void Progress::Add(int64_t done) {
  done_ += done;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  Draw(false);
}

void Progress::Draw(bool final) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int64_t done = done_.load();
  const double rate = seconds > 0 ? done / seconds : 0.0;
  const double eta = rate > 0 && total_ > done ? (total_ - done) / rate : 0.0;
  std::fprintf(stderr,
               "\r%s %lld/%lld %s  %.1f %s/s  ETA %.0f s   ",
               label_.c_str(),
               static_cast<long long>(done),
               static_cast<long long>(total_),
               unit_.c_str(),
               rate,
               unit_.c_str(),
               eta);
  if (final) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace lsds
