#include "evaluate/coco_eval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

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

namespace {

// accumulate's inner loop for one IoU threshold (cocoeval.py:380-410): the
// precision at the 101 recall thresholds and the final recall.
void PrecisionRecall(const std::vector<uint8_t>& tps,
                     const std::vector<uint8_t>& fps,
                     int64_t npig,
                     std::array<double, kR>* q,
                     double* recall) {
  const size_t nd = tps.size();
  std::vector<double> rc(nd), pr(nd);
  double tp = 0, fp = 0;
  for (size_t i = 0; i < nd; ++i) {
    tp += tps[i];
    fp += fps[i];
    rc[i] = tp / static_cast<double>(npig);
    pr[i] = tp / (fp + tp + std::numeric_limits<double>::epsilon());  // np.spacing(1)
  }
  *recall = nd ? rc.back() : 0;
  for (size_t i = nd > 0 ? nd - 1 : 0; i > 0; --i)
    if (pr[i] > pr[i - 1]) pr[i - 1] = pr[i];
  q->fill(0);
  // np.searchsorted(rc, recThrs, side='left'); an index past the end stops the
  // loop (the bare except of :403-408) and leaves the rest 0.
  for (int r = 0; r < kR; ++r) {
    const auto at = std::lower_bound(rc.begin(), rc.end(), RecallThresholds()[r]);
    if (at == rc.end()) break;
    (*q)[r] = pr[static_cast<size_t>(at - rc.begin())];
  }
}

constexpr uint32_t kRankBits = 7;  // ranks 0..99
constexpr uint32_t kRankMask = (1u << kRankBits) - 1;
static_assert(kLargestMaxDet <= (1 << kRankBits), "a rank fits its bits");
static_assert(kRankBits + 2 * kT <= 32, "the flags fit 32 bits");

bool TruePositive(uint32_t bits, int t) { return (bits >> (kRankBits + t)) & 1u; }
bool FalsePositive(uint32_t bits, int t) { return (bits >> (kRankBits + kT + t)) & 1u; }

}  // namespace

AccumulationBuilder::AccumulationBuilder(size_t categories)
    : records_(categories), counted_(categories, 0) {}

std::vector<uint32_t> AccumulationOrder(const DetectionBox* detections, size_t count) {
  std::vector<uint32_t> by_order(count);
  std::iota(by_order.begin(), by_order.end(), uint32_t{0});
  std::stable_sort(by_order.begin(), by_order.end(), [&](uint32_t a, uint32_t b) {
    if (detections[a].score != detections[b].score)
      return detections[a].score > detections[b].score;
    return detections[a].image_id < detections[b].image_id;
  });
  std::vector<uint32_t> order(count);
  for (size_t i = 0; i < count; ++i) order[by_order[i]] = static_cast<uint32_t>(i);
  return order;
}

void AccumulationBuilder::Add(const EvaluationCell& cell,
                              const CellResult& result,
                              const uint32_t* order) {
  counted_[cell.category] += result.ground_truth_counted;
  const size_t D = result.scores.size();
  for (size_t d = 0; d < D; ++d) {
    uint32_t flags = 0;
    for (int t = 0; t < kT; ++t) {
      const size_t at = t * D + d;
      if (result.ignored[at]) continue;  // dtIg: neither (cocoeval.py:377-378)
      flags |= 1u << (result.matched[at] ? t : kT + t);
    }
    if (flags == 0) continue;
    records_[cell.category].push_back(
        Record{order[cell.dts[d]], static_cast<uint32_t>(d) | flags << kRankBits});
  }
}

size_t AccumulationBuilder::kept_detections() const {
  size_t n = 0;
  for (const auto& r : records_) n += r.size();
  return n;
}

// accumulate (cocoeval.py:353-410): per category, each image's detections cut
// to maxDet and concatenated in image order, then sorted stably by score
// (:362-371), which is AccumulationOrder's.
Accumulation AccumulationBuilder::Finish(const std::vector<const AccumulationBuilder*>& parts) {
  const size_t K = parts.empty() ? 0 : parts.front()->records_.size();
  Accumulation a;
  a.categories = K;
  a.precision.assign(static_cast<size_t>(kT) * kR * K * kM, -1.0);
  a.recall.assign(static_cast<size_t>(kT) * K * kM, -1.0);
  for (const AccumulationBuilder* part : parts) a.images += part->images_;
  std::vector<Record> dets;
  for (size_t k = 0; k < K; ++k) {
    int64_t npig = 0;
    for (const AccumulationBuilder* part : parts) npig += part->counted_[k];
    a.ground_truth += npig;
    if (npig == 0) continue;  // :360-361, :372-374
    for (int m = 0; m < kM; ++m) {
      dets.clear();
      for (const AccumulationBuilder* part : parts)
        for (const Record& r : part->records_[k])
          if ((r.bits & kRankMask) < static_cast<uint32_t>(kMaxDetections[m])) dets.push_back(r);
      std::sort(dets.begin(), dets.end(), [](const Record& x, const Record& y) {
        return x.order < y.order;
      });
      for (int t = 0; t < kT; ++t) {
        std::vector<uint8_t> tps(dets.size()), fps(dets.size());
        for (size_t i = 0; i < dets.size(); ++i) {
          tps[i] = TruePositive(dets[i].bits, t);
          fps[i] = FalsePositive(dets[i].bits, t);
        }
        std::array<double, kR> q{};
        double recall = 0;
        PrecisionRecall(tps, fps, npig, &q, &recall);
        a.recall[(static_cast<size_t>(t) * K + k) * kM + m] = recall;
        for (int r = 0; r < kR; ++r)
          a.precision[((static_cast<size_t>(t) * kR + r) * K + k) * kM + m] = q[r];
        if (t == 0 && m == kM - 1) {
          a.matched_50 += std::accumulate(tps.begin(), tps.end(), int64_t{0});
          a.false_positives_50 += std::accumulate(fps.begin(), fps.end(), int64_t{0});
        }
      }
    }
  }
  return a;
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
  order_ = AccumulationOrder(data_.detections.data(), data_.detections.size());
}

CocoEvaluator::~CocoEvaluator() = default;

// COCOeval.accumulate (cocoeval.py:315-418) over the selected images.
Accumulation CocoEvaluator::Accumulate(const Selection& selection) const {
  AccumulationBuilder builder(data_.category_ids.size());
  for (int64_t image : data_.image_ids)
    if (!selection.image || selection.image(image)) builder.CountImage();
  for (const EvaluationCell& cell : cells_) {
    if (selection.image && !selection.image(cell.image_id)) continue;
    builder.Add(cell,
                EvaluateCell(cell,
                             data_.ground_truth.data(),
                             data_.detections.data(),
                             selection.ground_truth,
                             selection.detection),
                order_.data());
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
