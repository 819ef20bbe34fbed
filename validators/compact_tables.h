// The two tables `lsds validate` keeps across a streamed collection, stored as
// sorted vectors rather than node-based containers: a hash set or map costs
// 30 to 100 bytes of nodes and buckets per entry, which at a million frames
// (nine files each) is the whole memory of the command (docs/reliability.md,
// "Scale").
#ifndef LSDS_VALIDATORS_COMPACT_TABLES_H_
#define LSDS_VALIDATORS_COMPACT_TABLES_H_

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace lsds::validate {

// A set of 64-bit hashes at 8 bytes per distinct value. Inserts append; the
// vector is sorted and deduplicated whenever it has doubled since the last
// time, so many frames naming the same files do not grow it.
class HashSet64 {
 public:
  void Insert(uint64_t value) {
    values_.push_back(value);
    if (values_.size() >= 2 * sorted_ + 1024) Compact();
  }
  bool Contains(uint64_t value) {
    if (sorted_ != values_.size()) Compact();
    return std::binary_search(values_.begin(), values_.end(), value);
  }
  size_t size() {
    Compact();
    return values_.size();
  }

 private:
  void Compact() {
    std::sort(values_.begin(), values_.end());
    values_.erase(std::unique(values_.begin(), values_.end()), values_.end());
    sorted_ = values_.size();
  }
  std::vector<uint64_t> values_;
  size_t sorted_ = 0;  // values_[0, sorted_) are sorted and unique
};

// Values keyed by frame index, each taken at most once (a second frame with
// the same index finds nothing, as a duplicate deserves). Filled first, then
// taken from; when an index is added twice the last value counts.
template <typename Value>
class FrameTable {
 public:
  void Reserve(size_t n) { entries_.reserve(n); }  // no doubling past the frame count
  void Add(int64_t index, Value value) { entries_.push_back({index, std::move(value), false}); }

  // The value of `index` not taken yet, or nullptr; marks it taken.
  const Value* Take(int64_t index) {
    if (!sealed_) Seal();
    auto it =
        std::lower_bound(entries_.begin(), entries_.end(), index, [](const Entry& e, int64_t i) {
          return e.index < i;
        });
    if (it == entries_.end() || it->index != index || it->taken) return nullptr;
    it->taken = true;
    return &it->value;
  }

 private:
  struct Entry {
    int64_t index;
    Value value;
    bool taken;
  };
  void Seal() {
    const auto by_index = [](const Entry& a, const Entry& b) { return a.index < b.index; };
    // Files list frames in order as a rule; stable_sort's buffer (one more
    // table) is only paid when they do not.
    if (!std::is_sorted(entries_.begin(), entries_.end(), by_index))
      std::stable_sort(entries_.begin(), entries_.end(), by_index);
    // Keep the last of equal indices (stable sort kept their file order), in
    // place: a copy would double the table's peak.
    size_t kept = 0;
    for (size_t i = 0; i < entries_.size(); ++i) {
      if (kept > 0 && entries_[kept - 1].index == entries_[i].index)
        entries_[kept - 1] = std::move(entries_[i]);
      else if (kept != i)
        entries_[kept++] = std::move(entries_[i]);
      else
        ++kept;
    }
    entries_.resize(kept);
    sealed_ = true;
  }
  std::vector<Entry> entries_;
  bool sealed_ = false;
};

}  // namespace lsds::validate

#endif  // LSDS_VALIDATORS_COMPACT_TABLES_H_
