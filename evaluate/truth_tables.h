// The per-image and per-frame tables of the ground truth `lsds evaluate`
// holds while it streams the annotations (ground_truth.h): what grows with the
// images once the detections and records have their memory budget
// (docs/evaluate.md, "Memory"). Compact on purpose: sorted arrays searched by
// binary search instead of maps, every file name in one character arena,
// absent numbers as NaN, labels interned.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lsds::evaluate {

// One COCO image of the truth.
struct ImageEntry {
  int64_t id = 0;
  int64_t frame = 0;  // the collection's frame index (the image's lsds.frame)
  int32_t height = 0, width = 0;
  uint32_t name_begin = 0, name_size = 0;  // its file_name in the table's arena
};

class ImageTable {
 public:
  void Add(int64_t id, std::string_view file_name, int64_t frame, int64_t height, int64_t width);
  // Sorts by id (of a repeated id the last added stays) and indexes the file
  // names; lookups are valid after it.
  void Seal();

  const std::vector<ImageEntry>& images() const { return images_; }
  // Null when no image has the id.
  const ImageEntry* Find(int64_t id) const;
  // The image's entry; throws std::out_of_range (as std::map::at) when none.
  const ImageEntry& At(int64_t id) const;
  const ImageEntry* FindFileName(std::string_view file_name) const;
  std::string_view FileName(const ImageEntry& image) const {
    return std::string_view(names_).substr(image.name_begin, image.name_size);
  }

 private:
  std::vector<ImageEntry> images_;
  std::string names_;                 // every file name, one after the other
  std::vector<uint32_t> name_order_;  // positions in images_, by file name
};

// A label (cloud type, terrain material) held once for the process: frames
// point at it.
const std::string* InternLabel(std::string_view label);

// Per frame, what the collection records. Numbers are NaN when not recorded.
struct FrameFacts {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  int64_t index = 0;                    // the frame's index
  double gsd_m = kNone;                 // metadata.json gsd_m
  double altitude_agl_m = kNone;        // metadata.json altitude_agl_m
  double off_nadir_deg = kNone;         // optical axis from straight down
  double sun_elevation_deg = kNone;     // scene.sun.elevation_deg
  double fog_visibility_m = kNone;      // scene.atmosphere.visibility_m (clear: NaN)
  const std::string* clouds = nullptr;  // scene.sky.cloud_type ("none" at density 0), interned
  const std::string* terrain_material = nullptr;  // interned
  // The camera centre in world coordinates (world units), for the objects'
  // distances; NaN when unknown.
  std::array<double, 3> camera_in_world = {kNone, kNone, kNone};
  bool atmosphere_recorded = false;  // scene.atmosphere present
  // Per quota of the collection (EvaluationTruth::quotas): the bin the
  // frame's check achieved in the rendered truth; -1 when it achieved none
  // (the target out of view, a value outside every bin). Empty without quotas.
  std::vector<int16_t> quota_bins;

  bool camera_known() const { return !std::isnan(camera_in_world[0]); }
};

// A recorded number, or none for NaN.
inline std::optional<double> Recorded(double value) {
  if (std::isnan(value)) return std::nullopt;
  return value;
}

// The frames' facts, sorted by index.
class FrameTable {
 public:
  void Add(FrameFacts facts) { frames_.push_back(std::move(facts)); }
  void Seal();  // sorts by index (of a repeated index the last added stays)
  FrameFacts* Find(int64_t index);
  const FrameFacts* Find(int64_t index) const;
  size_t size() const { return frames_.size(); }

 private:
  std::vector<FrameFacts> frames_;
};

}  // namespace lsds::evaluate
