// The operating conditions `lsds evaluate` breaks metrics down by
// (docs/evaluate.md, "Conditions"): per object (size, visibility, in_frame,
// class, distance) and per frame (GSD, altitude, off-nadir angle, sun
// elevation, fog, clouds, terrain material, and each LCAP quota the collection
// was generated under), each cut into bins.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

enum class Level { kObject, kFrame };

// One condition and its bins.
struct ConditionBins {
  std::string name;  // "size_px", "visibility", ...
  std::string description;
  Level level = Level::kObject;
  std::vector<std::string> bins;  // bin labels, in the condition's order
  std::vector<double> edges;      // numeric: bins.size() + 1 edges; categorical: empty
  size_t definition = 0;          // which of ConditionNames(); unused for a quota
  // A quota of the collection's LCAP (EvaluationTruth::quotas[quota]): a frame
  // condition named "quota:NAME", binned by the quota's own bins at the value
  // the frame's check achieved; -1 for the built-in conditions.
  int quota = -1;
  std::vector<int64_t> planned;  // a quota: frames planned per bin (the whole run)
  // A condition a detection's box also has (size_px); for the others every
  // unmatched detection counts in every bin.
  bool bins_detections = false;
};

// An object as the conditions see it.
struct ObjectView {
  const ObjectFacts& facts;
  const std::string* category;  // its category's name; null: unknown
};

// The conditions the collection records (a condition no object or frame
// records is left out), from one pass over the truth's annotations.
std::vector<ConditionBins> BinConditions(const EvaluationTruth& truth);

// The bin of an object under an object condition, of an image (its frame's
// facts) under a frame condition, of a detection under a condition that bins
// detections; -1: not recorded (or not binned).
int ObjectBin(const ConditionBins& c, const ObjectView& object);
int FrameBin(const ConditionBins& c, const FrameFacts& facts);
int ImageBin(const ConditionBins& c, const EvaluationTruth& truth, int64_t image);
int DetectionBin(const ConditionBins& c, const DetectionBox& detection);

// The name of a category of the truth (null: none has that id).
const std::string* CategoryName(const EvaluationTruth& truth, int64_t category_id);

// The name of every condition BinConditions may give, in its order.
const std::vector<std::string>& ConditionNames();

}  // namespace lsds::evaluate
