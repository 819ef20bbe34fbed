// `lsds evaluate` (docs/evaluate.md): predictions against the collection's own
// truth, COCO's metrics and the same metrics per stratum of every condition;
// or, without predictions, the coverage of the condition space.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "evaluate/detections_by_image.h"
#include "evaluate/evaluate_report.h"
#include "evaluate/ground_truth.h"
#include "libs/util/limits.h"

namespace lsds::evaluate {

struct EvaluateOptions {
  TruthOptions truth;
  std::filesystem::path predictions;  // empty: coverage only
  std::string format = "coco";
  std::string iou_type = "bbox";  // COCOeval's iouType: bbox | segm; or obb (DOTA task 1)
  std::string ap = "voc07";       // obb: the DOTA devkit's VOC AP, voc07 | voc12; or coco
  std::filesystem::path output;   // JSON; empty: none
  std::filesystem::path junit;    // JUnit XML; empty: none
  std::filesystem::path suggest;  // the next LCAP capture; empty: none (needs predictions)
  bool force = false;
  int64_t thin_below = 30;
  std::vector<std::string> fail_under;  // METRIC=VALUE

  // Throws lsds::Error (exit 2) naming the flag at fault.
  void Check() const;
};

struct EvaluateResult {
  EvaluationReport report;
  bool thresholds_passed = true;              // false: exit 1
  std::vector<std::string> suggested_quotas;  // with --suggest
};

// Reads everything and computes the report before writing anything; then
// writes the outputs atomically (existing files only with `force`). Throws
// lsds::Error (exit 2) on bad input, naming the file and entry.
EvaluateResult RunEvaluate(const EvaluateOptions& options);

// The report of `truth` and `detections` (no files read or written). The
// detections and the accumulation records each take at most SpillShare of
// `memory_budget` in memory, the rest goes to a scratch file
// (docs/evaluate.md, "Memory"); the numbers are the same either way.
EvaluationReport Evaluate(const EvaluationTruth& truth,
                          std::vector<DetectionBox> detections,
                          int64_t thin_below,
                          uint64_t memory_budget = MemoryBudgetBytes());

// The same for detections already grouped by image.
EvaluationReport Evaluate(const EvaluationTruth& truth,
                          DetectionsByImage* detections,
                          int64_t thin_below,
                          uint64_t memory_budget = MemoryBudgetBytes());

// The share of the memory budget the detections held in memory may take, and
// the same share for the accumulation records: 1/32 (256 MiB of the default
// 8G), so that a large evaluation stays well under the budget whatever else
// the process holds.
inline uint64_t SpillShare(uint64_t memory_budget) { return memory_budget / 32; }

// The coverage report of `truth`.
EvaluationReport CoverageReport(const EvaluationTruth& truth, int64_t thin_below);

}  // namespace lsds::evaluate
