// `lsds evaluate` (docs/evaluate.md): predictions against the collection's own
// truth, COCO's metrics and the same metrics per stratum of every condition;
// or, without predictions, the coverage of the condition space.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "evaluate/evaluate_report.h"
#include "evaluate/ground_truth.h"

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

// The report of `truth` and `detections` (no files read or written).
EvaluationReport Evaluate(const EvaluationTruth& truth,
                          std::vector<DetectionBox> detections,
                          int64_t thin_below);

// The coverage report of `truth`.
EvaluationReport CoverageReport(const EvaluationTruth& truth, int64_t thin_below);

}  // namespace lsds::evaluate
