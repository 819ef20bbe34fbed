// COCOeval.accumulate (cocoapi 8c9bcc3, PythonAPI/pycocotools/cocoeval.py:
// 315-418) over records kept image by image: in memory while they fit the
// budget, in sorted runs on a scratch file above it, merged in accumulate's
// order, and the precision envelope computed in one forward pass
// (docs/evaluate.md, "Memory").
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/spill_file.h"

namespace lsds::evaluate {

class AccumulationRuns;

// What COCOeval.accumulate needs of every evaluated cell of one selection, and
// nothing more: per category the number of ground-truth boxes counted and the
// highest detection score, and per detection that counts somewhere a record:
// its score, its image's place in the sorted image ids, its rank in its image
// (for maxDets) and its true / false positive flags at the 10 IoU thresholds
// (16 bytes). accumulate's order (cocoeval.py:362-371: each image's detections
// by score, concatenated in image order, then sorted stably by score) is the
// order of (score descending, image place, rank). A detection that is ignored
// at every threshold is not kept: it adds neither a true nor a false
// positive, so the precision and recall it would repeat are those of the
// detection before it. Cells may be added in any order.
class AccumulationBuilder {
 public:
  struct Record {
    double score;
    uint32_t image;  // the image's place in the ascending image ids (COCOeval's p.imgIds)
    uint32_t bits;   // rank (7 bits), then 10 true-positive and 10 false-positive flags
  };

  explicit AccumulationBuilder(size_t categories);
  void CountImage() { ++images_; }
  // `image_index`: the place of the cell's image in the ascending image ids.
  void Add(const EvaluationCell& cell, const CellResult& result, uint32_t image_index);
  // COCOeval.accumulate over the cells of every one of `parts` (builders of
  // the same selection fed with different images) and, with `runs`, over the
  // records they spilled there as `selection`.
  static Accumulation Finish(const std::vector<const AccumulationBuilder*>& parts,
                             const AccumulationRuns* runs = nullptr,
                             size_t selection = 0);
  Accumulation Finish() const { return Finish({this}); }
  size_t held_records() const { return held_; }
  const std::deque<Record>& records(size_t category) const { return records_[category]; }

 private:
  friend class AccumulationRuns;
  // Per category; a deque grows by small blocks, without a vector's spare half.
  std::vector<std::deque<Record>> records_;
  std::vector<int64_t> counted_;   // ground truth counted, per category
  std::vector<double> top_score_;  // per category: the highest score of a detection (-inf: none)
  int64_t images_ = 0;
  size_t held_ = 0;
};

// The records of many selections' builders, in sorted runs on a scratch file
// (SpillFile): each run holds, per selection and category, the records the
// builders held when it was written, in accumulate's order.
class AccumulationRuns {
 public:
  // `memory_bytes`: what the readers of a merge may buffer between them.
  AccumulationRuns(size_t selections, size_t categories, uint64_t memory_bytes);
  ~AccumulationRuns();
  // Writes one run from `parts` ([selection] -> that selection's builders)
  // and empties their records.
  void Spill(const std::vector<std::vector<AccumulationBuilder*>>& parts);
  size_t runs() const { return segments_.size(); }
  uint64_t records() const { return records_; }

 private:
  friend class AccumulationBuilder;
  struct Segment {
    uint64_t offset = 0, count = 0;
  };
  size_t selections_, categories_;
  uint64_t memory_bytes_;
  std::unique_ptr<SpillFile> file_;
  std::vector<std::vector<Segment>> segments_;  // [run][selection * categories + category]
  uint64_t records_ = 0;
};

// accumulate's precision and recall for one category (cocoeval.py:375-410),
// the detections handed over one at a time in accumulate's order.
// cocoeval.py makes pr non-increasing from the right (:398-400) and reads it
// at the first detection whose recall reaches each threshold (searchsorted,
// :402-406), so q[r] = max pr[j] over the detections j with rc[j] >= r: each
// detection raises the bucket of the last threshold its recall reaches, and a
// suffix max over the 101 buckets gives q. The score at each threshold is the
// score of the first detection that reaches it (:406).
class PrecisionPass {
 public:
  explicit PrecisionPass(int64_t ground_truth_counted);
  void Add(const AccumulationBuilder::Record& record);
  // Writes category `k`'s precision, recall and scores into `a`, its counts at
  // IoU .5 too; `top_score`: the highest score of any detection of the
  // category, counted or not (none: -inf).
  void Finish(size_t k, double top_score, Accumulation* a) const;

 private:
  struct Curve {  // one IoU threshold and maxDets
    double tp = 0, fp = 0;
    int reached = 0;                                    // recall thresholds reached so far
    std::array<double, kRecallThresholdCount> best{};   // max pr with exactly `reached` reached
    std::array<double, kRecallThresholdCount> score{};  // the score that first reached each
  };
  double npig_;
  std::vector<Curve> curves_;  // [m][t]
};

}  // namespace lsds::evaluate
