// Deterministic train/val/test splits by a stable hash of each frame's group,
// so that the frames of one sequence (near-identical neighbours) never straddle
// two splits.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "libs/collection/model.h"

namespace lsds::convert {

struct SplitPart {
  std::string name;
  double fraction = 0;
};

// "train=0.8,val=0.2[,test=...]": names [A-Za-z0-9_-], fractions >= 0 summing
// to 1 (within 1e-6).
std::vector<SplitPart> ParseSplit(const std::string& spec);

// 64-bit FNV-1a of the bytes of `text`: stable across platforms, runs and
// versions.
uint64_t Fnv1a64(const std::string& text);

// The group a frame is split with: its sequence; frames without one are grouped
// in blocks of `block` consecutive frame indices ("#frames/<index / block>").
std::string SplitGroup(const Frame& frame, int64_t block = 50);

// SplitMix64's finalizer (Mix64, libs/util/splitmix64.h) follows FNV-1a:
// FNV-1a alone leaves its top bits poorly mixed for names that differ only in
// their last characters ("seq_1", "seq_2"), which would skew the split
// proportions.

// The split of a group: u = top 53 bits of Mix64(FNV-1a(group)) / 2^53 in [0,
// 1), the first part whose cumulative fraction exceeds u.
const std::string& AssignSplit(const std::vector<SplitPart>& parts, const std::string& group);
// The same, as the position of the part in `parts`.
size_t AssignSplitIndex(const std::vector<SplitPart>& parts, const std::string& group);

// The split of every frame of a conversion. The hash rule above (whole groups)
// is used when it fills every split with a non-zero fraction; otherwise (few
// sequences, e.g. one) the frames, ordered by group then index, are cut into
// one contiguous block per split sized by the fractions (each at least one
// frame), so a requested split is never empty and neighbours mostly stay
// together. Fewer frames than such splits is an error naming the split that
// cannot be filled.
struct SplitPlan {
  std::vector<std::string> names;  // the parts' names, in --split order
  // (frame index, position in `names`), sorted by index: 16 bytes a frame,
  // where a map of names took about 100 (a million-frame conversion keeps
  // one entry per frame).
  std::vector<std::pair<int64_t, uint32_t>> split_of_frame;
  bool blocks = false;  // true when the block rule was needed

  // The split of frame `index` (std::out_of_range for a frame not planned).
  const std::string& SplitOf(int64_t index) const;
};
struct SplitFrame {
  int64_t index;
  std::string group;  // SplitGroup(frame)
};
SplitPlan PlanSplits(const std::vector<SplitPart>& parts, const std::vector<SplitFrame>& frames);

}  // namespace lsds::convert
