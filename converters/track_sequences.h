// What the tracking formats (mot, visdrone-vid) and VisDrone DET share: the
// sequences of a split (one per sequence, shot and rig camera), their 1-based
// frame numbers and track ids, the objects a frame writes (kept ones and the
// ones written as "ignore"), and the shared images linked under the names those
// formats expect (docs/convert.md, "mot").
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "converters/converter.h"

namespace lsds::convert {

// An object a tracking-style format writes in a frame: a kept object
// (considered = true), or one a filter (--min-visibility, --min-pixels,
// --min-transmittance, --drop-truncated) dropped that is still visible and of
// an output class (considered = false: MOT's conf 0 and VisDrone's score 0,
// ground truth the evaluations leave out; docs/convert.md).
struct TrackObject {
  const ObjectTruth* truth = nullptr;
  int class_index = 0;
  Box2d box;  // the visible box, clipped to the image
  bool considered = true;
};

// The kept objects of `frame` and the filtered-out ones still worth an
// ignore row, in the collection's order.
std::vector<TrackObject> TrackObjects(const FrameContext& frame, const ClassMap& classes);

// Counts, under `reason`, the objects TrackObjects writes as ignored.
void CountIgnored(const std::vector<TrackObject>& objects,
                  const ClassMap& classes,
                  const char* reason,
                  LossReport* loss);

// One output sequence: the frames of one split with the same sequence, shot and
// rig camera, numbered 1.. in frame order.
struct TrackSequence {
  std::string name;  // a file name: [A-Za-z0-9_-], unique in the split
  int width = 0, height = 0;
  std::vector<int64_t> frame_indices;  // collection frame index of frame number k + 1
  std::vector<double> times;           // seconds, of the same frames
  std::map<uint32_t, int> ids;         // instance id -> 1-based track id, by first appearance
  std::string rows;                    // the format's annotation text, written at the end

  int64_t frames() const { return static_cast<int64_t>(frame_indices.size()); }
  // The 1-based track id of an instance (a new one at its first appearance).
  int TrackId(uint32_t instance_id);
  // Frames per second from the median time step (1 for a single frame or
  // times that do not increase).
  double FrameRate() const;
};

// The sequences of every split, created as frames arrive in order.
class TrackSequences {
 public:
  // The sequence `frame` belongs to, with the frame appended (its number is
  // then frames()).
  TrackSequence& Add(const FrameContext& frame);
  // The sequences of `split` in order of first frame.
  std::vector<const TrackSequence*> OfSplit(const std::string& split) const;

 private:
  using Key = std::tuple<std::string, std::string, int64_t, std::string>;  // split, sequence,
                                                                           // shot, camera
  std::map<Key, size_t> index_;
  std::vector<std::pair<std::string, TrackSequence>> sequences_;  // (split, sequence)
  std::set<std::pair<std::string, std::string>> names_used_;      // (split, name)
};

// Makes `link` name the same file as `image` (a hard link; a copy where links
// are not possible), creating its folder. The images of the formats that
// expect their own folders cost no space.
void LinkImage(const std::filesystem::path& image, const std::filesystem::path& link);

// "%.Nf" without trailing zeros (and without a trailing '.').
std::string TrimmedFixed(double value, int decimals);

}  // namespace lsds::convert
