// A COCO results file (docs/evaluate.md, "Predictions"): a JSON list of
// {image_id | file_name, category_id, bbox: [x, y, w, h], score}, checked entry
// by entry against the ground truth.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

// Throws lsds::Error at `file#/INDEX/KEY[/i]` for an empty file, a document that
// is not a list of objects, an image or category the ground truth does not
// have, a missing or non-finite number (NaN and Infinity, which Python's
// json.dump writes, included), a negative width or height.
std::vector<DetectionBox> ReadCocoPredictions(const std::filesystem::path& file,
                                              const EvaluationTruth& truth);

// The same handing each entry to `on_detection` as it is read, in file order.
void ReadCocoPredictions(const std::filesystem::path& file,
                         const EvaluationTruth& truth,
                         const std::function<void(DetectionBox&&)>& on_detection);

// The same for a document in memory (`file` names it in messages).
std::vector<DetectionBox> ParseCocoPredictions(const std::string& text,
                                               const std::string& file,
                                               const EvaluationTruth& truth);

}  // namespace lsds::evaluate
