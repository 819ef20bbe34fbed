// DOTA task-1 text files as the devkit reads them (dota_evaluation_task1.py
// at CAPTAIN-WHU/DOTA_devkit 9938855): label files `x1 y1 ... x4 y4 class
// [difficult]` (parse_gt, :21-53) and result files `Task1_<class>.txt` with
// lines `image score x1 y1 ... x4 y4` (voc_eval, :158-169).
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "evaluate/dota_eval.h"

namespace lsds::evaluate {

// The objects of one label file of `image` (its stem), by parse_gt's rules:
// each line stripped and split on one space, lines of fewer than 9 tokens
// skipped (the `imagesource:` and `gsd:` header among them), difficult the
// 10th token or 0. Throws lsds::Error at `file:line` for a corner that is not
// a number.
std::vector<DotaObject> ParseDotaLabels(const std::string& text,
                                        const std::string& file,
                                        const std::string& image);

// Every `Task1_<class>.txt` of `folder` for the classes of `class_names`
// (a class without a file has no detections). Throws lsds::Error (exit 2)
// naming the file and line for a folder without any Task1 file, a Task1 file
// of a class the ground truth does not have, a line that is not `image score`
// and eight numbers, a number that is not finite, an image not in `images`.
std::vector<DotaDetection> ReadDotaResults(const std::filesystem::path& folder,
                                           const std::vector<std::string>& class_names,
                                           const std::set<std::string>& images);

}  // namespace lsds::evaluate
