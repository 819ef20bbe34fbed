// The operating conditions `lsds evaluate` breaks metrics down by
// (docs/evaluate.md, "Conditions"): per object (size, visibility, in_frame,
// class, distance) and per frame (GSD, altitude, off-nadir angle, sun
// elevation, fog, clouds, terrain material), each cut into bins.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

enum class Level { kObject, kFrame };

// One condition with every object (or frame) put into a bin.
struct ConditionBins {
  std::string name;  // "size_px", "visibility", ...
  std::string description;
  Level level = Level::kObject;
  std::vector<std::string> bins;     // bin labels, in the condition's order
  std::vector<double> edges;         // numeric: bins.size() + 1 edges; categorical: empty
  std::vector<int> object_bin;       // per ground-truth annotation; -1: not recorded
  std::map<int64_t, int> image_bin;  // frame conditions: per COCO image id (absent: not recorded)
  // Per detection, for a condition a box also has (size_px); empty otherwise:
  // then every unmatched detection counts in every bin.
  std::vector<int> detection_bin;
};

// The conditions the collection records (a condition no object or frame
// records is left out). `detections` may be empty (coverage).
std::vector<ConditionBins> BinConditions(const EvaluationTruth& truth,
                                         const std::vector<DetectionBox>& detections);

// The name of every condition BinConditions may give, in its order.
const std::vector<std::string>& ConditionNames();

}  // namespace lsds::evaluate
