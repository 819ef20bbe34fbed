// Ultralytics' prediction text files (`yolo predict save_txt=True
// save_conf=True`: one `<image stem>.txt` per image, written by
// ultralytics/engine/results.py Results.save_txt) read as detections:
// `class cx cy w h conf [track id]` for boxes, `class x1 y1 ... xn yn conf`
// for a segment model's polygons, `class x1 y1 ... x4 y4 conf
// [track id]` for oriented boxes, coordinates normalised by the image size
// (docs/evaluate.md, "YOLO predictions").
#pragma once

#include <filesystem>
#include <vector>

#include "evaluate/coco_eval.h"
#include "evaluate/dota_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

// Boxes: class c is COCO category c + 1 (as lsds convert --to yolo and --to
// coco number them). Throws lsds::Error (exit 2) at `file:line` for a file
// that is no image of the ground truth, a line without a confidence, a class
// the ground truth does not have, a number that is not finite.
std::vector<DetectionBox> ReadYoloDetections(const std::filesystem::path& folder,
                                             const EvaluationTruth& truth);

// Polygons (a segment model's `class x1 y1 ... xn yn conf`), as masks for
// iouType segm: each rasterized as Ultralytics rasterizes a label polygon
// (polygon2mask), its area the mask's pixels, its box the mask's.
std::vector<DetectionBox> ReadYoloSegmentDetections(const std::filesystem::path& folder,
                                                    const EvaluationTruth& truth);

// Oriented boxes: class c is the c-th of `class_names` (dota_classes.txt),
// the image its stem, corners in pixels.
std::vector<DotaDetection> ReadYoloObbDetections(const std::filesystem::path& folder,
                                                 const EvaluationTruth& truth,
                                                 const std::vector<std::string>& class_names);

}  // namespace lsds::evaluate
