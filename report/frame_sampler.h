// Evenly spread frames from a stream of unknown length, in one pass and bounded
// memory: keep every stride-th frame and double the stride whenever twice the
// target is kept (docs/report.md, "Sampling").
#pragma once

#include <algorithm>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

namespace lsds::report {

template <typename T>
class FrameSampler {
 public:
  // At most `target` frames (--sample): those whose index is in `always`
  // (frames that validation findings point to; the first `target` of them in
  // stream order), and the rest of the target spread evenly.
  explicit FrameSampler(size_t target, std::set<int64_t> always = {})
      : target_(target), always_(std::move(always)) {}

  // Offer the frames in stream order; `index` is the frame's index.
  void Offer(int64_t index, const T& item) {
    const int64_t position = seen_++;
    if (always_.count(index) > 0 && forced_.size() < target_) {
      forced_.emplace_back(position, item);
      return;
    }
    if (target_ == 0 || position % stride_ != 0) return;
    kept_.emplace_back(position, item);
    if (kept_.size() >= 2 * target_) {
      std::vector<std::pair<int64_t, T>> thinned;
      for (auto& entry : kept_) {
        if (entry.first % (2 * stride_) == 0) thinned.push_back(std::move(entry));
      }
      kept_ = std::move(thinned);
      stride_ *= 2;
    }
  }

  int64_t seen() const { return seen_; }

  // The forced frames and evenly spaced ones, at most `target` in all, in
  // stream order.
  std::vector<T> Take() {
    std::vector<std::pair<int64_t, T>> out;
    const size_t n = kept_.size();
    const size_t spread = target_ - forced_.size();
    if (n <= spread) {
      out = std::move(kept_);
    } else {
      for (size_t k = 0; k < spread; ++k) {
        out.push_back(std::move(kept_[(2 * k + 1) * n / (2 * spread)]));
      }
    }
    for (auto& entry : forced_) out.push_back(std::move(entry));
    std::sort(
        out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<T> items;
    for (auto& entry : out) items.push_back(std::move(entry.second));
    kept_.clear();
    forced_.clear();
    return items;
  }

 private:
  size_t target_;
  std::set<int64_t> always_;
  int64_t seen_ = 0;
  int64_t stride_ = 1;
  std::vector<std::pair<int64_t, T>> kept_;
  std::vector<std::pair<int64_t, T>> forced_;
};

}  // namespace lsds::report
