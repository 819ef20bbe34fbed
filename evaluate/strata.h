// Metrics per stratum of every condition, ranked worst to best, and the
// coverage of the condition space (docs/evaluate.md, "Strata", "Coverage").
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/conditions.h"
#include "evaluate/detections_by_image.h"

namespace lsds::evaluate {

// 95 % Wilson score interval of a binomial proportion k / n ([0, 1] for n = 0).
struct Interval {
  double low = 0, high = 1;
};
Interval WilsonInterval(int64_t k, int64_t n);

struct StratumMetrics {
  std::string label;
  int64_t objects = 0;  // ground-truth boxes counted (crowd regions are not)
  int64_t frames = 0;   // images holding them (frame conditions: images in the stratum)
  int64_t matched_50 = 0;
  int64_t false_positives_50 = 0;
  double ap = -1, ap50 = -1, ar100 = -1;  // COCO's means; -1: nothing to average
  double recall_50 = 0;                   // matched_50 / objects (0 without objects)
  Interval recall_50_ci;
  bool thin = false;  // objects < the thin threshold
};

struct ConditionMetrics {
  std::string name, description;
  Level level = Level::kObject;
  std::vector<StratumMetrics> strata;  // worst first: recall_50, then CI upper bound, then label
};

// One bin of the coverage histogram.
struct CoverageCell {
  std::string label;
  int64_t objects = 0;   // ground-truth boxes in the bin
  int64_t frames = 0;    // frames in the bin (object conditions: frames holding such an object)
  int64_t planned = -1;  // a quota's bin: the frames its LCAP planned (the whole run); -1: none
  std::string flag;      // "empty", "thin" or ""
};

struct ConditionCoverage {
  std::string name, description;
  Level level = Level::kObject;
  int64_t unrecorded = 0;           // objects (frames) whose value the collection does not record
  std::vector<CoverageCell> cells;  // in the condition's bin order
};

// What one pass over the truth's images gives. A cell of coverage is "empty"
// with no object (frame conditions: no frame) and "thin" with fewer than
// `thin_below`.
struct ImageMetrics {
  std::optional<CocoStats> stats;        // with detections
  Accumulation all;                      // no area range: the counts at IoU .5
  std::vector<ConditionMetrics> strata;  // with detections
  std::vector<ConditionCoverage> coverage;
  size_t kept_detections = 0;  // the accumulations' records, over all selections
  size_t spilled_runs = 0;     // the runs of records written to the scratch file
};

// Evaluates the images one at a time as the truth hands them out (several at
// once on the TBB threads), each against its own detections as soon as both
// are known, keeping only what COCOeval.accumulate needs per area range and
// stratum (AccumulationBuilder, evaluate/accumulation.h): in memory up to
// `record_memory_bytes`, in sorted runs on a scratch file above it.
// `detections` (null: coverage only) are taken image by image.
ImageMetrics EvaluateImages(const EvaluationTruth& truth,
                            const std::vector<ConditionBins>& conditions,
                            DetectionsByImage* detections,
                            int64_t thin_below,
                            uint64_t record_memory_bytes = std::numeric_limits<uint64_t>::max());

// Coverage only (no detections).
inline ImageMetrics EvaluateImages(const EvaluationTruth& truth,
                                   const std::vector<ConditionBins>& conditions,
                                   std::nullptr_t,
                                   int64_t thin_below) {
  return EvaluateImages(truth, conditions, static_cast<DetectionsByImage*>(nullptr), thin_below);
}

// The same with every detection in memory, in file order.
ImageMetrics EvaluateImages(const EvaluationTruth& truth,
                            const std::vector<ConditionBins>& conditions,
                            const std::vector<DetectionBox>* detections,
                            int64_t thin_below);

}  // namespace lsds::evaluate
