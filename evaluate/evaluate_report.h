// What `lsds evaluate` reports (docs/evaluate.md, "Output"): the JSON document
// (schemas/evaluate.schema.json), the text summary and the JUnit XML, and the
// --fail-under thresholds.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evaluate/coco_eval.h"
#include "evaluate/dota_eval.h"
#include "evaluate/strata.h"

namespace lsds::evaluate {

// --fail-under METRIC=VALUE: METRIC one of CocoStatNames().
struct Threshold {
  std::string metric;
  double value = 0;
  double actual = 0;  // filled in by CheckThresholds
  bool passed = true;
};

// Throws lsds::Error (exit 2) naming the flag for an unknown metric or a value
// that is not a finite number.
Threshold ParseThreshold(const std::string& text);

// Fills in `actual` and `passed`; true when every threshold passed.
bool CheckThresholds(const CocoStats& stats, std::vector<Threshold>* thresholds);

struct EvaluationReport {
  std::string collection;                  // as given
  std::optional<std::string> predictions;  // none: coverage only
  int64_t images = 0, annotations = 0, detections = 0;
  std::vector<std::pair<int64_t, std::string>> categories;
  int64_t thin_below = 0;
  std::string iou_type = "bbox";  // COCOeval's iouType: bbox, segm; or obb (the DOTA devkit)
  std::optional<CocoStats> stats;
  Accumulation all;  // area "all": the counts at IoU .5
  std::vector<ConditionMetrics> strata;
  std::vector<ConditionCoverage> coverage;
  std::vector<Threshold> thresholds;
  std::optional<DotaResult> dota;  // --iou-type obb: the DOTA devkit's task-1 metrics
};

nlohmann::json ReportJson(const EvaluationReport& report);
std::string ReportText(const EvaluationReport& report);
std::string ReportJUnit(const EvaluationReport& report);

}  // namespace lsds::evaluate
