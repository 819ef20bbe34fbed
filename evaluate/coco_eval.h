// Box detection metrics computed exactly as the reference COCO API's COCOeval
// does for iouType "bbox" (cocodataset/cocoapi, PythonAPI/pycocotools/
// cocoeval.py and common/maskApi.c at commit 8c9bcc3, the source of every rule
// cited as cocoeval.py:LINE below; docs/evaluate.md).
//
// COCOeval's area ranges are one case of a Selection: which images count,
// which ground-truth boxes count (the others are ignored, like crowd regions)
// and which unmatched detections count. The strata of docs/evaluate.md are
// other selections evaluated by the same code.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "libs/masks/coco_rle.h"

namespace lsds::evaluate {

// COCOeval's iouType: "bbox" compares boxes (maskApi.c bbIou), "segm" masks
// (rleIou, cocoeval.py:178-180); and lsds' "obb", oriented boxes compared by
// the DOTA devkit's polygon IoU (QuadIou, dota_eval.h) under COCO's rules.
enum class IouType { kBox, kMask, kQuad };

// COCO's [x, y, width, height], pixel-edge.
struct BoxXywh {
  double x = 0, y = 0, w = 0, h = 0;
};

struct GroundTruthBox {
  int64_t id = 0;  // > 0: COCOeval records a match by the annotation id (cocoeval.py:295)
  int64_t image_id = 0;
  int64_t category_id = 0;
  BoxXywh bbox;
  double area = 0;  // the annotation's `area` (the mask pixel count from lsds convert)
  bool iscrowd = false;
  // Counted by no selection, as a box outside the area range (a DOTA object
  // marked difficult: docs/evaluate.md, "Oriented boxes").
  bool ignored = false;
  masks::CocoRle mask;       // IouType::kMask only
  std::vector<double> quad;  // IouType::kQuad only: x1 y1 ... x4 y4, pixels
};

// One entry of a COCO results list. Its id is its position + 1 and its area
// w * h, as COCO.loadRes sets them (coco.py:333-340).
struct DetectionBox {
  int64_t image_id = 0;
  int64_t category_id = 0;
  BoxXywh bbox;  // with a mask and no box given: the mask's (rleToBbox, coco.py:346-347)
  double score = 0;
  masks::CocoRle mask;       // IouType::kMask only
  std::vector<double> quad;  // IouType::kQuad only
  // COCO.loadRes's area when it is not w * h: a mask result file whose first
  // entry has no bbox gives every entry its mask's area (coco.py:341-345).
  std::optional<double> area;

  double Area() const { return area ? *area : bbox.w * bbox.h; }
};

struct CocoData {
  std::vector<int64_t> image_ids;     // every image of the ground truth
  std::vector<int64_t> category_ids;  // every category of the ground truth
  std::vector<GroundTruthBox> ground_truth;
  std::vector<DetectionBox> detections;  // for images and categories listed above
  IouType iou_type = IouType::kBox;
};

// What one evaluation counts (empty functions: everything). A ground-truth box
// that is not selected is ignored as COCOeval ignores one outside the area
// range (cocoeval.py:250-254); an unmatched detection that is not selected is
// ignored as one outside the area range (cocoeval.py:297-299). Crowd regions
// are always ignored (cocoeval.py:107-109).
struct Selection {
  std::function<bool(int64_t image_id)> image;
  std::function<bool(size_t ground_truth_index)> ground_truth;
  std::function<bool(size_t detection_index)> detection;
};

inline constexpr int kIouThresholdCount = 10;      // .50:.05:.95
inline constexpr int kRecallThresholdCount = 101;  // 0:.01:1
inline constexpr std::array<int, 3> kMaxDetections = {1, 10, 100};

// np.linspace(.5, 0.95, 10) and np.linspace(.0, 1.00, 101) bit for bit
// (cocoeval.py:506-507).
const std::array<double, kIouThresholdCount>& IouThresholds();
const std::array<double, kRecallThresholdCount>& RecallThresholds();

// COCOeval.accumulate's arrays for one selection, plus counts at IoU .5 and
// 100 detections per image.
struct Accumulation {
  size_t categories = 0;
  std::vector<double> precision;   // [t][r][k][m], -1 where nothing was counted
  std::vector<double> recall;      // [t][k][m], -1 where nothing was counted
  std::vector<double> scores;      // [t][r][k][m]: accumulate's `scores`, -1 likewise
  int64_t images = 0;              // images selected
  int64_t ground_truth = 0;        // ground-truth boxes counted (not ignored)
  int64_t matched_50 = 0;          // of them, matched at IoU .5
  int64_t false_positives_50 = 0;  // detections counted and unmatched at IoU .5

  double Precision(int t, int r, size_t k, int m) const;
  double Recall(int t, size_t k, int m) const;
};

// COCOeval's _summarize (cocoeval.py:427-457): the mean of the entries > -1
// at one IoU threshold (index) or all of them, for maxDets index `m`; -1 when
// there is none.
double MeanPrecision(const Accumulation& a, std::optional<int> iou_index, int m);
double MeanRecall(const Accumulation& a, std::optional<int> iou_index, int m);
// The index of an IoU threshold compared for equality with the linspace
// values, as np.where(iouThr == p.iouThrs) does (cocoeval.py:442); none when
// no threshold is equal.
std::optional<int> IouIndex(double threshold);

// COCOeval.stats (cocoeval.py:458-472): AP, AP50, AP75, APs, APm, APl, AR1,
// AR10, AR100, ARs, ARm, ARl.
using CocoStats = std::array<double, 12>;
const std::array<const char*, 12>& CocoStatNames();

// The boxes of one image and category (COCOeval._gts/_dts[imgId, catId],
// cocoeval.py:114-117) as indices into the arrays they were grouped from: the
// ground truth in file order, the detections by score (highest first, ties in
// file order), cut to 100 (cocoeval.py:173-176), and their IoUs [dt][gt]
// (computeIoU, cocoeval.py:163-190).
struct EvaluationCell {
  int64_t image_id = 0;
  size_t category = 0;  // index into the sorted category ids
  std::vector<size_t> gts, dts;
  std::vector<double> ious;
};

// Groups `gts` and `detections` per image and category (those of unknown
// images or categories are not evaluated: getAnnIds(imgIds, catIds),
// cocoeval.py:96-97) and computes their IoUs, in category then image order.
// `image_ids` and `category_ids` sorted and unique.
std::vector<EvaluationCell> MakeCells(const GroundTruthBox* gts,
                                      size_t gt_count,
                                      const DetectionBox* detections,
                                      size_t detection_count,
                                      const std::vector<int64_t>& image_ids,
                                      const std::vector<int64_t>& category_ids,
                                      IouType iou_type);

// evaluateImg's arrays (cocoeval.py:301-313) for one cell and selection, with
// maxDet = 100.
struct CellResult {
  std::vector<double> scores;        // D
  std::vector<uint8_t> matched;      // [t][d]
  std::vector<uint8_t> ignored;      // [t][d]
  int64_t ground_truth_counted = 0;  // gtIgnore == 0
};

// COCOeval.evaluateImg (cocoeval.py:235-313): `selected_gt(i)` and
// `selected_detection(i)` are asked about the cell's indices into `gts` and
// `detections` (empty functions: everything).
CellResult EvaluateCell(const EvaluationCell& cell,
                        const GroundTruthBox* gts,
                        const DetectionBox* detections,
                        const std::function<bool(size_t)>& selected_gt,
                        const std::function<bool(size_t)>& selected_detection);

class CocoEvaluator {
 public:
  // Groups the boxes per image and category and computes their IoUs once
  // (COCOeval.evaluate and computeIoU, cocoeval.py:121-190).
  explicit CocoEvaluator(CocoData data);
  ~CocoEvaluator();
  CocoEvaluator(const CocoEvaluator&) = delete;
  CocoEvaluator& operator=(const CocoEvaluator&) = delete;

  const CocoData& data() const { return data_; }
  Accumulation Accumulate(const Selection& selection) const;
  CocoStats Stats() const;

 private:
  CocoData data_;
  std::vector<EvaluationCell> cells_;  // category, then image order
};

// COCOeval.summarize for detections (cocoeval.py:458-472) from the
// accumulations of the four area ranges (all, small, medium, large).
CocoStats StatsOf(const std::array<Accumulation, 4>& area_ranges);

// Params.setDetParams' area ranges (cocoeval.py:509): [0, 1e5^2], [0, 32^2],
// [32^2, 96^2], [96^2, 1e5^2]; an area a is in [low, high] unless a < low or
// a > high (cocoeval.py:250-254, :297-299).
const std::array<std::pair<double, double>, 4>& CocoAreaRanges();
inline bool InAreaRange(double area, const std::pair<double, double>& range) {
  return !(area < range.first || area > range.second);
}

// COCO's area ranges as selections: all, small, medium, large
// (cocoeval.py:509-510).
Selection AreaRange(const CocoData& data, double low, double high);

}  // namespace lsds::evaluate
