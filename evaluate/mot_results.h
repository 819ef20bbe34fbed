// MOTChallenge tracker files read as detections (docs/evaluate.md, "MOT
// predictions"): one `<SEQ>.txt` per sequence, as TrackEval reads a tracker's
// data folder (trackeval/datasets/mot_challenge_2d_box.py), lines
// `frame,id,bb_left,bb_top,bb_width,bb_height,conf[,x,y,z]`, frame numbers and
// box corners 1-based, sequences and frame numbers as lsds convert --to mot
// writes them.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

// Throws lsds::Error (exit 2) at `file:line` for a file of no sequence, a line
// of fewer than 7 fields, a frame number the sequence does not have, a number
// that is not finite, a negative size; and for a ground truth of more than one
// category (tracker files carry no class).
std::vector<DetectionBox> ReadMotDetections(const std::filesystem::path& folder,
                                            const EvaluationTruth& truth,
                                            const MotSequences& sequences);

}  // namespace lsds::evaluate
