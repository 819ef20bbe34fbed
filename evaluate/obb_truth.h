// The oriented-box truth of `lsds evaluate --iou-type obb`: the objects `lsds
// convert --to dota` writes, chosen by the DOTA converter's own rule
// (convert::DotaLabelOf) in the same converter pass that writes the COCO
// truth, each joined by its image and instance id to the facts of its COCO
// annotation, so that every condition bins oriented boxes as it bins boxes
// (docs/evaluate.md, "Oriented boxes").
#pragma once

#include <vector>

#include "evaluate/dota_eval.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

struct ObbTruth {
  // As the DOTA devkit reads the label files: objects by image stem (sorted),
  // then in the converter's order.
  DotaTruth dota;
  // The same objects for COCO's rules (DotaAsCoco: quads, a difficult object
  // ignored), held in memory, `objects` their facts; iou_type kQuad.
  EvaluationTruth truth;
};

// Throws lsds::Error (exit 2) for an unreadable collection or bad options.
ObbTruth ReadObbTruth(const TruthOptions& options);

// DOTA detections as COCO results against `obb` (DotaAsCoco).
std::vector<DetectionBox> ObbDetections(const ObbTruth& obb,
                                        const std::vector<DotaDetection>& detections);

}  // namespace lsds::evaluate
