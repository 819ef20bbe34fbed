#include "evaluate/coco_eval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

#include "evaluate/accumulation.h"
#include "evaluate/dota_eval.h"

namespace lsds::evaluate {

namespace {

constexpr int kT = kIouThresholdCount;
constexpr int kR = kRecallThresholdCount;
constexpr int kM = static_cast<int>(kMaxDetections.size());
constexpr int kLargestMaxDet = kMaxDetections.back();

// maskApi.c bbIou, for one pair (the order of every operation kept, so that a
// box exactly at a threshold falls on the same side).
double BoxIou(const BoxXywh& d, const BoxXywh& g, bool crowd) {
  const double ga = g.w * g.h;
  const double da = d.w * d.h;
  const double w = std::fmin(d.w + d.x, g.w + g.x) - std::fmax(d.x, g.x);
  if (w <= 0) return 0;
  const double h = std::fmin(d.h + d.y, g.h + g.y) - std::fmax(d.y, g.y);
  if (h <= 0) return 0;
  const double i = w * h;
  const double u = crowd ? da : da + ga - i;
  return i / u;
}

Quad QuadOf(const std::vector<double>& corners) {
  Quad q{};
  std::copy_n(corners.begin(), std::min(corners.size(), q.size()), q.begin());
  return q;
}

// np.argsort(-scores, kind='mergesort') over `indices`: a stable sort, highest
// score first, ties in their given order.
void SortByScore(const DetectionBox* detections, std::vector<size_t>* indices) {
  std::stable_sort(indices->begin(), indices->end(), [&](size_t a, size_t b) {
    return detections[a].score > detections[b].score;
  });
}

}  // namespace

const std::array<double, kIouThresholdCount>& IouThresholds() {
  // numpy's linspace: y = arange(num) * step + start, the last set to stop.
  static const std::array<double, kIouThresholdCount> thresholds = [] {
    std::array<double, kIouThresholdCount> t{};
    const double step = (0.95 - 0.5) / (kIouThresholdCount - 1);
    for (int i = 0; i < kIouThresholdCount; ++i) {
      const double product = static_cast<double>(i) * step;
      t[i] = product + 0.5;
    }
    t[kIouThresholdCount - 1] = 0.95;
    return t;
  }();
  return thresholds;
}

const std::array<double, kRecallThresholdCount>& RecallThresholds() {
  static const std::array<double, kRecallThresholdCount> thresholds = [] {
    std::array<double, kRecallThresholdCount> r{};
    const double step = 1.0 / (kRecallThresholdCount - 1);
    for (int i = 0; i < kRecallThresholdCount; ++i) r[i] = static_cast<double>(i) * step + 0.0;
    r[kRecallThresholdCount - 1] = 1.0;
    return r;
  }();
  return thresholds;
}

std::optional<int> IouIndex(double threshold) {
  for (int t = 0; t < kT; ++t)
    if (IouThresholds()[t] == threshold) return t;
  return std::nullopt;
}

const std::array<const char*, 12>& CocoStatNames() {
  static const std::array<const char*, 12> names = {
      "AP", "AP50", "AP75", "APs", "APm", "APl", "AR1", "AR10", "AR100", "ARs", "ARm", "ARl"};
  return names;
}

double Accumulation::Precision(int t, int r, size_t k, int m) const {
  return precision[((static_cast<size_t>(t) * kR + r) * categories + k) * kM + m];
}

double Accumulation::Recall(int t, size_t k, int m) const {
  return recall[(static_cast<size_t>(t) * categories + k) * kM + m];
}

std::vector<EvaluationCell> MakeCells(const GroundTruthBox* gts,
                                      size_t gt_count,
                                      const DetectionBox* detections,
                                      size_t detection_count,
                                      const std::vector<int64_t>& image_ids,
                                      const std::vector<int64_t>& category_ids,
                                      IouType iou_type) {
  std::map<int64_t, size_t> category_index;
  for (size_t k = 0; k < category_ids.size(); ++k) category_index[category_ids[k]] = k;
  std::map<std::pair<size_t, int64_t>, EvaluationCell> cells;
  const auto cell_of = [&](int64_t image, int64_t category) -> EvaluationCell* {
    const auto k = category_index.find(category);
    if (k == category_index.end() || !std::binary_search(image_ids.begin(), image_ids.end(), image))
      return nullptr;
    EvaluationCell& cell = cells[{k->second, image}];
    cell.image_id = image;
    cell.category = k->second;
    return &cell;
  };
  for (size_t i = 0; i < gt_count; ++i)
    if (EvaluationCell* cell = cell_of(gts[i].image_id, gts[i].category_id)) cell->gts.push_back(i);
  for (size_t i = 0; i < detection_count; ++i) {
    const DetectionBox& d = detections[i];
    if (EvaluationCell* cell = cell_of(d.image_id, d.category_id)) cell->dts.push_back(i);
  }
  // computeIoU: detections sorted by score, cut to maxDets[-1]
  // (cocoeval.py:173-176), IoUs of every pair (maskUtils.iou, :188-189).
  std::vector<EvaluationCell> out;
  out.reserve(cells.size());
  for (auto& entry : cells) {
    EvaluationCell& cell = entry.second;
    SortByScore(detections, &cell.dts);
    if (cell.dts.size() > static_cast<size_t>(kLargestMaxDet)) cell.dts.resize(kLargestMaxDet);
    cell.ious.resize(cell.dts.size() * cell.gts.size());
    for (size_t d = 0; d < cell.dts.size(); ++d) {
      for (size_t g = 0; g < cell.gts.size(); ++g) {
        const GroundTruthBox& gt = gts[cell.gts[g]];
        const DetectionBox& dt = detections[cell.dts[d]];
        double iou = 0;
        if (iou_type == IouType::kMask) {
          iou = masks::CocoRleIou(dt.mask, gt.mask, gt.iscrowd);
        } else if (iou_type == IouType::kQuad) {
          iou = QuadIou(QuadOf(gt.quad), QuadOf(dt.quad));
        } else {
          iou = BoxIou(dt.bbox, gt.bbox, gt.iscrowd);
        }
        cell.ious[d * cell.gts.size() + g] = iou;
      }
    }
    out.push_back(std::move(cell));
  }
  return out;
}

namespace {

// evaluateImg's matching at one IoU threshold (cocoeval.py:273-296): each
// detection, best score first, takes the ground truth of highest IoU at or
// above the threshold that is not yet matched (crowd regions may be matched
// again), preferring boxes that are not ignored. `order` is the ground truth
// with the ignored last; `matched` and `ignored` are the detections' flags.
void MatchAtThreshold(double threshold,
                      const std::vector<double>& ious,
                      const std::vector<uint8_t>& crowd,
                      const std::vector<uint8_t>& ignore,
                      const std::vector<size_t>& order,
                      uint8_t* matched,
                      uint8_t* ignored) {
  const size_t G = order.size(), D = G ? ious.size() / G : 0;
  std::vector<uint8_t> gt_matched(G, 0);  // gtm[t] > 0, in the sorted order
  for (size_t d = 0; d < D; ++d) {
    double best = std::min(threshold, 1 - 1e-10);  // :276
    int m = -1;
    for (size_t s = 0; s < G; ++s) {
      const size_t g = order[s];
      if (gt_matched[s] && !crowd[g]) continue;             // :280-281
      if (m > -1 && !ignore[order[m]] && ignore[g]) break;  // :283-284
      const double iou = ious[d * G + g];
      if (iou < best) continue;  // :286-287
      best = iou;
      m = static_cast<int>(s);
    }
    if (m == -1) continue;
    ignored[d] = ignore[order[m]];  // :294-296
    matched[d] = 1;
    gt_matched[m] = 1;
  }
}

}  // namespace

CellResult EvaluateCell(const EvaluationCell& cell,
                        const GroundTruthBox* gts,
                        const DetectionBox* detections,
                        const std::function<bool(size_t)>& selected_gt,
                        const std::function<bool(size_t)>& selected_detection) {
  const size_t G = cell.gts.size(), D = cell.dts.size();
  // _ignore: crowd, or outside the selection (cocoeval.py:250-254); ignored
  // ground truth sorted last, stably (:257-258).
  std::vector<uint8_t> ignore(G), crowd(G);
  for (size_t g = 0; g < G; ++g) {
    const size_t index = cell.gts[g];
    crowd[g] = gts[index].iscrowd;
    ignore[g] = crowd[g] || gts[index].ignored || (selected_gt && !selected_gt(index));
  }
  std::vector<size_t> order(G);
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(
      order.begin(), order.end(), [&](size_t a, size_t b) { return ignore[a] < ignore[b]; });
  CellResult result;
  result.scores.resize(D);
  result.matched.assign(kT * D, 0);
  result.ignored.assign(kT * D, 0);
  for (size_t d = 0; d < D; ++d) result.scores[d] = detections[cell.dts[d]].score;
  for (size_t g = 0; g < G; ++g) result.ground_truth_counted += ignore[g] ? 0 : 1;
  // maskUtils.iou returns [] without ground truth or detections (:263, :272).
  for (int t = 0; G > 0 && D > 0 && t < kT; ++t) {
    MatchAtThreshold(IouThresholds()[t],
                     cell.ious,
                     crowd,
                     ignore,
                     order,
                     &result.matched[t * D],
                     &result.ignored[t * D]);
  }
  // Unmatched detections outside the selection are ignored (:297-299).
  for (size_t d = 0; d < D; ++d) {
    if (!selected_detection || selected_detection(cell.dts[d])) continue;
    for (int t = 0; t < kT; ++t)
      if (!result.matched[t * D + d]) result.ignored[t * D + d] = 1;
  }
  return result;
}

CocoEvaluator::CocoEvaluator(CocoData data) : data_(std::move(data)) {
  // COCOeval.evaluate: unique sorted image and category ids (cocoeval.py:134-136).
  for (std::vector<int64_t>* ids : {&data_.image_ids, &data_.category_ids}) {
    std::sort(ids->begin(), ids->end());
    ids->erase(std::unique(ids->begin(), ids->end()), ids->end());
  }
  cells_ = MakeCells(data_.ground_truth.data(),
                     data_.ground_truth.size(),
                     data_.detections.data(),
                     data_.detections.size(),
                     data_.image_ids,
                     data_.category_ids,
                     data_.iou_type);
}

CocoEvaluator::~CocoEvaluator() = default;

// COCOeval.accumulate (cocoeval.py:315-418) over the selected images.
Accumulation CocoEvaluator::Accumulate(const Selection& selection) const {
  AccumulationBuilder builder(data_.category_ids.size());
  for (int64_t image : data_.image_ids)
    if (!selection.image || selection.image(image)) builder.CountImage();
  for (const EvaluationCell& cell : cells_) {
    if (selection.image && !selection.image(cell.image_id)) continue;
    const auto image =
        std::lower_bound(data_.image_ids.begin(), data_.image_ids.end(), cell.image_id);
    builder.Add(cell,
                EvaluateCell(cell,
                             data_.ground_truth.data(),
                             data_.detections.data(),
                             selection.ground_truth,
                             selection.detection),
                static_cast<uint32_t>(image - data_.image_ids.begin()));
  }
  return builder.Finish();
}

double MeanPrecision(const Accumulation& a, std::optional<int> iou_index, int m) {
  double sum = 0;
  int64_t n = 0;
  for (int t = 0; t < kT; ++t) {
    if (iou_index && *iou_index != t) continue;
    for (int r = 0; r < kR; ++r) {
      for (size_t k = 0; k < a.categories; ++k) {
        const double p = a.Precision(t, r, k, m);
        if (p > -1) sum += p, ++n;
      }
    }
  }
  return n ? sum / static_cast<double>(n) : -1;
}

double MeanRecall(const Accumulation& a, std::optional<int> iou_index, int m) {
  double sum = 0;
  int64_t n = 0;
  for (int t = 0; t < kT; ++t) {
    if (iou_index && *iou_index != t) continue;
    for (size_t k = 0; k < a.categories; ++k) {
      const double r = a.Recall(t, k, m);
      if (r > -1) sum += r, ++n;
    }
  }
  return n ? sum / static_cast<double>(n) : -1;
}

const std::array<std::pair<double, double>, 4>& CocoAreaRanges() {
  static const double big = 1e5 * 1e5;
  static const std::array<std::pair<double, double>, 4> ranges = {
      {{0, big}, {0, 32 * 32}, {32 * 32, 96 * 96}, {96 * 96, big}}};
  return ranges;
}

Selection AreaRange(const CocoData& data, double low, double high) {
  Selection s;
  s.ground_truth = [&data, low, high](size_t i) {
    return InAreaRange(data.ground_truth[i].area, {low, high});
  };
  s.detection = [&data, low, high](size_t i) {
    return InAreaRange(data.detections[i].Area(), {low, high});
  };
  return s;
}

CocoStats StatsOf(const std::array<Accumulation, 4>& area) {
  const int m100 = kM - 1;
  // A threshold that is not one of the linspace values selects nothing: -1.
  const auto at = [&](double threshold) {
    const std::optional<int> t = IouIndex(threshold);
    return t ? MeanPrecision(area[0], t, m100) : -1.0;
  };
  return {MeanPrecision(area[0], std::nullopt, m100),
          at(0.5),
          at(0.75),
          MeanPrecision(area[1], std::nullopt, m100),
          MeanPrecision(area[2], std::nullopt, m100),
          MeanPrecision(area[3], std::nullopt, m100),
          MeanRecall(area[0], std::nullopt, 0),
          MeanRecall(area[0], std::nullopt, 1),
          MeanRecall(area[0], std::nullopt, m100),
          MeanRecall(area[1], std::nullopt, m100),
          MeanRecall(area[2], std::nullopt, m100),
          MeanRecall(area[3], std::nullopt, m100)};
}

// COCOeval.summarize for detections (cocoeval.py:458-472).
CocoStats CocoEvaluator::Stats() const {
  std::array<Accumulation, 4> area;
  for (size_t i = 0; i < area.size(); ++i)
    area[i] = Accumulate(AreaRange(data_, CocoAreaRanges()[i].first, CocoAreaRanges()[i].second));
  return StatsOf(area);
}

}  // namespace lsds::evaluate
