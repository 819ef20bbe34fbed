#include "generator/lang/capture/timeline.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <tuple>

#include "generator/lang/vocabulary.h"
#include "libs/util/strings.h"

namespace lsds {

std::vector<std::string> TimingKeys() { return KindVocabulary("timing").Spellings(); }

std::pair<std::string, int64_t> RefWithNumber(const Node& n) {
  if (n->is_object() && n->size() == 1) {
    const auto [key, value] = n.Members().front();
    const double v = ReadNumber(value);
    if (v < 1 || v != std::floor(v) || v > 1e6) value.Fail("expected a whole number >= 1");
    return {key, static_cast<int64_t>(v)};
  }
  const std::string s = ReadString(n);
  const size_t colon = s.find(':');
  if (colon == std::string::npos) return {s, -1};
  const std::string num = s.substr(colon + 1);
  char* end = nullptr;
  const long long v = std::strtoll(num.c_str(), &end, 10);
  if (num.empty() || *end != '\0' || v < 0 || v > 1000000)
    n.Fail("expected NAME:NUMBER, found '" + s + "'");
  return {s.substr(0, colon), static_cast<int64_t>(v)};
}

std::vector<Node> Blocks(const Node& value) {
  std::vector<Node> blocks;
  if (value->is_array())
    for (size_t i = 0; i < value->size(); ++i) blocks.push_back(value.Item(i));
  else
    blocks.push_back(value);
  return blocks;
}

std::vector<std::string> PathNames(const Program& capture) {
  std::vector<std::string> names;
  for (const Definition& d : capture.definitions)
    if (d.kind == "path") names.push_back(d.symbol);
  return names;
}

const Definition& NamedPath(const Program& capture, const Node& item, const std::string& symbol) {
  const Definition* path = capture.Find(symbol);
  if (!path || path->kind != "path")
    item.Fail("'" + symbol + "' is not a path" + DidYouMean(symbol, PathNames(capture)));
  return *path;
}

Timeline::Timeline(const Program& capture,
                   const IsCameraEntry& is_camera_entry,
                   const FrameCount& count)
    : capture_(capture) {
  const Definition* current_collection = nullptr;
  // Instances are numbered along the whole timeline, so that every sequence name is unique: a path
  // flown by two moves (or two collections) is P(1) then P(2).
  std::map<const Definition*, int64_t> flown;
  auto append = [&](const Definition& path, int64_t repetitions) {
    for (int64_t r = 1; r <= repetitions; ++r) {
      Segment s;
      s.path = &path;
      s.repetition = ++flown[&path];
      s.first = steps();
      s.count = count(path, segments_.size());
      s.collection = current_collection;
      segments_.push_back(s);
    }
  };
  bool moved = false;
  for (const Definition& c : capture.definitions) {
    if (c.kind != "collection") continue;
    current_collection = &c;
    for (const auto& [key, value] : c.body.Members()) {
      if (!is_camera_entry(key, value)) continue;
      for (const Node& block : Blocks(value)) {
        block.CheckKeys({"move"}, "camera entry of " + c.symbol);
        const Node move = block.Find("move");
        if (!move) block.Fail("a camera entry needs move:[P1:3, ...]");
        for (const Node& item : Blocks(move)) {
          const auto [symbol, reps] = RefWithNumber(item);
          append(NamedPath(capture, item, symbol), reps < 0 ? 1 : reps);
          moved = true;
        }
      }
    }
  }
  if (!moved)
    for (const Definition& d : capture.definitions)
      if (d.kind == "path") append(d, 1);
}

int64_t Timeline::steps() const {
  return segments_.empty() ? 0 : segments_.back().first + segments_.back().count;
}

const Segment& Timeline::At(int64_t step) const {
  const Segment* seg = nullptr;
  for (const Segment& s : segments_)
    if (step >= s.first && step < s.first + s.count) seg = &s;
  return *seg;
}

std::pair<int64_t, int64_t> Timeline::Span(const Node& where,
                                           const std::string& symbol,
                                           int64_t rep) const {
  int64_t lo = -1, hi = -1;
  const Definition* named = capture_.Find(symbol);
  if (named && named->kind == "collection") {
    // A set/collection: the frames of the paths its camera moves fly.
    if (rep >= 0) where.Fail("a collection has no repetitions: write '" + symbol + "'");
    for (const Segment& s : segments_) {
      if (s.collection != named) continue;
      if (lo < 0) lo = s.first;
      hi = s.first + s.count;
    }
    if (lo < 0) where.Fail("collection '" + symbol + "' moves the camera along no path");
    return {lo, hi};
  }
  for (const Segment& s : segments_) {
    if (s.path->symbol != symbol || (rep >= 0 && s.repetition != rep)) continue;
    if (lo < 0) lo = s.first;
    hi = s.first + s.count;
  }
  if (lo < 0) {
    if (capture_.Find(symbol) && rep >= 0)
      where.Fail("path '" + symbol + "' has no repetition " + std::to_string(rep) +
                 " in the camera's moves");
    where.Fail("'" + symbol + "' is not a path the camera moves along" +
               DidYouMean(symbol, PathNames(capture_)));
  }
  return {lo, hi};
}

namespace {

int64_t FrameNumber(const Node& v) {
  const double f = ReadNumber(v);
  if (f < 0 || f != std::floor(f) || f > 1e9) v.Fail("a frame number is a whole number >= 0");
  return static_cast<int64_t>(f);
}

}  // namespace

void ReadTiming(const Node& block, const Timeline& timeline, RuleTiming* timing) {
  for (const auto& [key, v] : block.Members()) {
    const std::string k = CanonicalKey(key);
    if (k == "when") {
      if (v->is_number()) {
        timing->begin = static_cast<int64_t>(ReadNumber(v));
      } else {
        v.CheckKeys({"after", "during", "frame"}, "when");
        ReadTiming(v, timeline, timing);
      }
    } else if (k == "after") {
      if (v->is_number()) {  // after frame N: from frame N + 1 on
        timing->begin = FrameNumber(v) + 1;
      } else {
        const auto [symbol, rep] = RefWithNumber(v);
        timing->begin = timeline.Span(v, symbol, rep).second;
      }
    } else if (k == "during") {
      if (v->is_number()) {  // during frame N: that frame only
        timing->begin = FrameNumber(v);
        timing->end = timing->begin + 1;
      } else {
        const auto [symbol, rep] = RefWithNumber(v);
        std::tie(timing->begin, timing->end) = timeline.Span(v, symbol, rep);
      }
      timing->during = true;
    } else if (k == "frame") {
      const double f = ReadNumber(v);
      if (f < 0 || f != std::floor(f)) v.Fail("frame must be a whole number >= 0");
      timing->begin = static_cast<int64_t>(f);
    }
  }
}

}  // namespace lsds
