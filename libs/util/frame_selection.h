// The one `--frames` grammar of every lsds command (docs/cli.md): frame
// indices as a Python slice, half-open.
//   A:B  indices A .. B-1     A:  A to the last     :B  the first to B-1
//   N    the single frame N (as Python's x[N])
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace lsds {

// Frame indices [begin, end): the one frame-range type of lsds, taken by every
// library function that works on part of a collection or a plan. "To the
// last frame" is end == kToTheEnd, never a second sentinel.
struct FrameRange {
  static constexpr int64_t kToTheEnd = std::numeric_limits<int64_t>::max();
  int64_t begin = 0;
  int64_t end = kToTheEnd;  // exclusive

  bool Contains(int64_t index) const { return index >= begin && index < end; }
  bool bounded() const { return end != kToTheEnd; }
  bool all() const { return begin <= 0 && !bounded(); }  // every frame index (all are >= 0)
};

// A parsed --frames: the range and the text the user gave, for messages.
struct FrameSelection : FrameRange {
  std::string text;
};

// Parses the text of `flag`; throws lsds::Error located at the flag ("--frames
// 5:2: ...") for anything that is not one of the four forms with indices >= 0
// and A < B.
FrameSelection ParseFrameSelection(const std::string& text, const std::string& flag = "--frames");

// Checks the selection against the frame indices that exist (`available`,
// increasing), e.g. a collection's or a plan's. Throws lsds::Error (exit 2)
// naming the valid range when the selection reaches outside
// [available.front(), available.back()] or selects no frame: an out-of-range
// --frames is never an empty output. `what` names the frames' owner ("the
// collection", "the plan").
void CheckFrameSelection(const FrameSelection& selection,
                         const std::vector<int64_t>& available,
                         const std::string& what,
                         const std::string& flag = "--frames");

}  // namespace lsds
