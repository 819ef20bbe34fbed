// Oriented-box detection metrics computed as the DOTA devkit's task-1
// evaluation does (CAPTAIN-WHU/DOTA_devkit at 9938855, dota_evaluation_task1.py
// and polyiou.cpp, the source of every rule cited as task1.py:LINE and
// polyiou.cpp:LINE below; docs/evaluate.md, "Oriented boxes"): per class, the
// PASCAL VOC average precision at one polygon IoU threshold, and their mean.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "evaluate/coco_eval.h"

namespace lsds::evaluate {

// Four corners x1 y1 ... x4 y4, pixels, as a DOTA label line has them.
using Quad = std::array<double, 8>;

// polyiou.cpp iou_poly: the IoU of two quadrilaterals (convex or not, either
// winding), the intersection summed over triangle pairs of their fans.
double QuadIou(const Quad& p, const Quad& q);

// The area of a quadrilateral (the shoelace formula, either winding).
double QuadArea(const Quad& q);

struct DotaObject {
  std::string image;  // the label file's stem ("000007")
  std::string class_name;
  Quad quad{};
  bool difficult = false;
};

struct DotaDetection {
  std::string image;
  std::string class_name;
  double score = 0;
  Quad quad{};
};

// voc_ap (task1.py:54-85): VOC 2007's 11 recall points, or the area under the
// precision envelope (VOC 2010-2012).
enum class VocAp { k07, k12 };

struct DotaClassResult {
  std::string class_name;
  int64_t objects = 0;     // not difficult (npos, task1.py:153)
  int64_t difficult = 0;   // ignored: neither true nor false positives when matched
  int64_t detections = 0;  // of this class
  int64_t true_positives = 0;
  std::optional<double> ap;  // none without objects (the devkit divides by 0)
};

struct DotaResult {
  VocAp ap = VocAp::k07;
  double iou_threshold = 0.5;
  std::vector<DotaClassResult> classes;  // in the order given
  std::optional<double> map;             // mean over classes with an AP
};

// voc_eval (task1.py:88-270) for every class of `class_names`: detections
// sorted by score, highest first (ties in file order: numpy's argsort is not
// stable, so the devkit may order ties otherwise); each takes the object of
// highest IoU among those whose upright boxes overlap (the +1 pixel rule of
// task1.py:199-227), and is a true positive above the threshold on an object
// not yet taken, a false positive otherwise, neither on a difficult one.
DotaResult EvaluateDota(const std::vector<std::string>& class_names,
                        const std::vector<DotaObject>& objects,
                        const std::vector<DotaDetection>& detections,
                        VocAp ap,
                        double iou_threshold = 0.5);

// The same objects and detections for COCO's rules with the polygon IoU
// (IouType::kQuad, `--ap coco`): category c + 1 for the c-th of
// `class_names`, the image id `image_ids` gives the label file's stem, each
// box's area its quadrilateral's, its upright box the corners' extent, a
// difficult object ignored (as one outside the area range).
CocoData DotaAsCoco(const std::vector<std::string>& class_names,
                    const std::vector<DotaObject>& objects,
                    const std::vector<DotaDetection>& detections,
                    const std::map<std::string, int64_t>& image_ids);

}  // namespace lsds::evaluate
