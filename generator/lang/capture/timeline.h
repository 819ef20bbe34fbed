// The capture's timeline (docs/languages.md, "Collections"): the path instances the camera flies,
// one after the other, as frame spans; and the timing of scene changes (`after`, `during`,
// `frame`) resolved against those spans.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "generator/lang/scene.h"

namespace lsds {

// One path instance of the timeline: the `repetition`-th flight of `path` along the whole timeline
// (its sequence name is PATH(repetition)), frames [first, first + count) (time steps, with a rig).
struct Segment {
  const Definition* path = nullptr;
  const Definition* collection = nullptr;  // whose move flies it, if any
  int64_t repetition = 1;                  // 1-based
  int64_t first = 0;                       // global frame index of its first frame
  int64_t count = 0;
};

class Timeline {
 public:
  // Whether a collection entry `key: value` moves the camera.
  using IsCameraEntry = std::function<bool(const std::string& key, const Node& value)>;
  // The frame count of a path instance at place `segment` of the timeline.
  using FrameCount = std::function<int64_t(const Definition& path, uint64_t segment)>;

  // The camera's moves of every collection in file order (`move:[P1:3, P2]`), each path repeated;
  // with no move anywhere, every path once in file order.
  Timeline(const Program& capture, const IsCameraEntry& is_camera_entry, const FrameCount& count);

  const std::vector<Segment>& segments() const { return segments_; }
  // The number of time steps of all segments.
  int64_t steps() const;
  // The segment of time step `step` (< steps()).
  const Segment& At(int64_t step) const;
  // The frame span [lo, hi) of path instance `symbol:rep` (rep < 0: all its instances) or of a
  // collection's paths; an error at `where` when the camera never flies it.
  std::pair<int64_t, int64_t> Span(const Node& where, const std::string& symbol, int64_t rep) const;

 private:
  const Program& capture_;
  std::vector<Segment> segments_;
};

// When a scene change is in effect: frames [begin, end).
struct RuleTiming {
  int64_t begin = 0;                                  // first frame in effect
  int64_t end = std::numeric_limits<int64_t>::max();  // one past the last (during)
  bool during = false;                                // drawn on every frame, not once
};

// Reads `when`, `after`, `during` and `frame` of `block` into `timing`.
void ReadTiming(const Node& block, const Timeline& timeline, RuleTiming* timing);

// The timing keys of a collection entry (vocabulary.h).
std::vector<std::string> TimingKeys();

// "P1:3" / "P1" / {"P1": 3} -> (symbol, number or -1).
std::pair<std::string, int64_t> RefWithNumber(const Node& n);

// A value that is one block or a list of them, as a list.
std::vector<Node> Blocks(const Node& value);

// The symbols of the capture's paths, in file order.
std::vector<std::string> PathNames(const Program& capture);

// The path `item` names (`P1:2` names P1), or an error at `item`.
const Definition& NamedPath(const Program& capture, const Node& item, const std::string& symbol);

}  // namespace lsds
