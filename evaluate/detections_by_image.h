// The user's detections grouped by image for `lsds evaluate`, which reads
// them in file order (a results file is not ordered by image) and evaluates
// image by image: held in memory while they fit the budget, in runs sorted by
// image on a scratch file above it (docs/evaluate.md, "Memory").
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/spill_file.h"

namespace lsds::evaluate {

class DetectionsByImage {
 public:
  // `memory_bytes`: what the detections held in memory may take (estimated:
  // the structure and its mask and polygon); past it they go to a run.
  explicit DetectionsByImage(uint64_t memory_bytes);
  ~DetectionsByImage();
  DetectionsByImage(const DetectionsByImage&) = delete;
  DetectionsByImage& operator=(const DetectionsByImage&) = delete;

  // In file order, before the first Take.
  void Add(DetectionBox detection);
  int64_t size() const { return count_; }
  size_t runs() const { return run_extents_.size(); }

  // The detections of `image_id` in file order (the order COCOeval breaks
  // score ties in). Images are asked in increasing id order; the detections
  // of images skipped are dropped.
  std::vector<DetectionBox> Take(int64_t image_id);

 private:
  struct Run {
    std::unique_ptr<SpillReader> reader;
    uint64_t left = 0;  // entries not yet read
    bool has_head = false;
    DetectionBox head;  // the next entry, read ahead
  };
  void Spill();
  void StartReading();
  static void Advance(Run* run);

  uint64_t memory_bytes_;
  int64_t count_ = 0;
  std::vector<DetectionBox> held_;
  uint64_t held_bytes_ = 0;
  std::unique_ptr<SpillFile> file_;
  std::vector<std::pair<uint64_t, uint64_t>> run_extents_;  // offset, entries
  std::vector<Run> runs_;
  bool reading_ = false;
  size_t held_at_ = 0;  // the next held entry to hand out
};

}  // namespace lsds::evaluate
