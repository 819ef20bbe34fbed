// MOTChallenge tracker files read as detections (docs/evaluate.md, "MOT
// predictions"): one `<SEQ>.txt` per sequence, as TrackEval reads a tracker's
// data folder (trackeval/datasets/mot_challenge_2d_box.py at JonathonLuiten/
// TrackEval 12c8791, cited as mot_challenge_2d_box.py:LINE), lines
// `frame,id,bb_left,bb_top,bb_width,bb_height,conf[,class[,...]]`, frame
// numbers and box corners 1-based, sequences (one per shot and rig camera),
// frame numbers and class ids as lsds convert --to mot writes them.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

// The categories of the truth whose MOT17 class is one of TrackEval's
// distractors (person_on_vehicle, static_person, distractor, reflection;
// mot_challenge_2d_box.py:325-328), with `mot_classes` "mot17"; none with
// "order".
std::set<int64_t> MotDistractorCategories(const EvaluationTruth& truth,
                                          const std::string& mot_classes);

// Each row's class is its 8th field (1 in a row of 7, :249-253), the class id
// lsds convert --to mot writes with `mot_classes` (order: the COCO category
// id; mot17: MOT17's id of the category's name); with one category, every
// class up to 1 is it (TrackEval's one class, :351-355, MOT17's -1
// placeholder included). Rows that match (TrackEval's assignment at IoU .5,
// :373-382) an object of a distractor category are left out. Throws
// lsds::Error (exit 2) at `file:line` for a file of no sequence, a line of
// fewer than 7 fields, a frame number the sequence does not have, a number
// that is not finite, a negative size, a class the truth does not have.
std::vector<DetectionBox> ReadMotDetections(const std::filesystem::path& folder,
                                            const EvaluationTruth& truth,
                                            const MotSequences& sequences,
                                            const std::string& mot_classes);

}  // namespace lsds::evaluate
