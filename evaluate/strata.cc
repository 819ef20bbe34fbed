#include "evaluate/strata.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <tuple>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "evaluate/accumulation.h"

namespace lsds::evaluate {

namespace {

constexpr double kZ95 = 1.959963984540054;  // the 97.5 % quantile of the normal distribution

// Images evaluated at once on the TBB threads; fewer when the records may
// take little memory, since they are spilled between batches only.
size_t ImagesPerBatch(uint64_t record_memory_bytes) {
  return static_cast<size_t>(std::clamp<uint64_t>(record_memory_bytes >> 16, 1, 256));
}

// What COCOeval evaluates an image for: everything, the four area ranges, and
// one bin of a condition (a stratum): the images of a frame condition's bin;
// for an object condition every image, its objects in the bin counted and the
// others ignored, and the unmatched detections of that bin (every one when
// the condition does not bin detections).
struct Selections {
  static constexpr size_t kFirstStratum = 5;
  std::vector<std::pair<size_t, int>> strata;  // (condition, bin)
  size_t size() const { return kFirstStratum + strata.size(); }
};

// The counts of one pass (per thread, merged at the end).
struct Tally {
  std::vector<AccumulationBuilder> builders;          // per selection
  std::vector<std::vector<int64_t>> objects, frames;  // per condition and bin
  std::vector<int64_t> unrecorded;                    // per condition

  Tally(size_t selections, size_t categories, const std::vector<ConditionBins>& conditions)
      : builders(selections, AccumulationBuilder(categories)), unrecorded(conditions.size(), 0) {
    for (const ConditionBins& c : conditions) {
      objects.emplace_back(c.bins.size(), 0);
      frames.emplace_back(c.bins.size(), 0);
    }
  }
  // The counts of `other` (its builders are read where they are).
  void AddCounts(const Tally& other) {
    for (size_t c = 0; c < objects.size(); ++c) {
      unrecorded[c] += other.unrecorded[c];
      for (size_t b = 0; b < objects[c].size(); ++b) {
        objects[c][b] += other.objects[c][b];
        frames[c][b] += other.frames[c][b];
      }
    }
  }
};

// One image with its detections, in file order.
struct ImageWork {
  TruthImage truth;
  std::vector<DetectionBox> detections;
  uint32_t image_index = 0;  // the image's place in the ascending image ids
};

class ImageEvaluator {
 public:
  ImageEvaluator(const EvaluationTruth& truth,
                 const std::vector<ConditionBins>& conditions,
                 const Selections& selections,
                 std::vector<int64_t> category_ids,
                 bool with_detections)
      : truth_(truth),
        conditions_(conditions),
        selections_(selections),
        category_ids_(std::move(category_ids)),
        with_detections_(with_detections) {}

  void Evaluate(const ImageWork& work, Tally* tally) const {
    const TruthImage& image = work.truth;
    const size_t G = image.boxes.size();
    // Every object's (and for a frame condition the image's) bin.
    std::vector<int> frame_bin(conditions_.size(), -1);
    std::vector<std::vector<int>> object_bin(conditions_.size(), std::vector<int>(G, -1));
    for (size_t c = 0; c < conditions_.size(); ++c) {
      const ConditionBins& condition = conditions_[c];
      if (condition.level == Level::kFrame) {
        frame_bin[c] = ImageBin(condition, truth_, image.image_id);
        std::fill(object_bin[c].begin(), object_bin[c].end(), frame_bin[c]);
      } else {
        for (size_t g = 0; g < G; ++g)
          object_bin[c][g] = ObjectBin(
              condition,
              ObjectView{image.objects[g], CategoryName(truth_, image.boxes[g].category_id)});
      }
      Count(c, image, frame_bin[c], object_bin[c], tally);
    }
    if (!with_detections_) return;
    std::vector<std::vector<int>> detection_bin(conditions_.size());
    for (size_t c = 0; c < conditions_.size(); ++c) {
      if (!conditions_[c].bins_detections) continue;
      for (const DetectionBox& d : work.detections)
        detection_bin[c].push_back(DetectionBin(conditions_[c], d));
    }
    const std::vector<EvaluationCell> cells = MakeCells(image.boxes.data(),
                                                        G,
                                                        work.detections.data(),
                                                        work.detections.size(),
                                                        truth_.coco.image_ids,
                                                        category_ids_,
                                                        truth_.coco.iou_type);
    const auto evaluate = [&](size_t s,
                              const std::function<bool(size_t)>& gt,
                              const std::function<bool(size_t)>& detection) {
      AccumulationBuilder& builder = tally->builders[s];
      builder.CountImage();
      for (const EvaluationCell& cell : cells)
        builder.Add(cell,
                    EvaluateCell(cell, image.boxes.data(), work.detections.data(), gt, detection),
                    work.image_index);
    };
    evaluate(0, {}, {});
    for (size_t a = 0; a < CocoAreaRanges().size(); ++a) {
      const std::pair<double, double>& range = CocoAreaRanges()[a];
      evaluate(
          1 + a,
          [&](size_t g) { return InAreaRange(image.boxes[g].area, range); },
          [&](size_t d) { return InAreaRange(work.detections[d].Area(), range); });
    }
    for (size_t i = 0; i < selections_.strata.size(); ++i) {
      const auto [c, bin] = selections_.strata[i];
      const size_t s = Selections::kFirstStratum + i;
      if (conditions_[c].level == Level::kFrame) {
        if (frame_bin[c] == bin) evaluate(s, {}, {});
        continue;
      }
      const std::vector<int>& objects = object_bin[c];
      const std::vector<int>& detections = detection_bin[c];
      std::function<bool(size_t)> detection;
      if (conditions_[c].bins_detections)
        detection = [&detections, b = bin](size_t d) { return detections[d] == b; };
      evaluate(
          s, [&objects, b = bin](size_t g) { return objects[g] == b; }, detection);
    }
  }

 private:
  // Coverage: objects per bin (crowd regions not), and frames per bin (object
  // conditions: frames holding such an object).
  void Count(size_t c,
             const TruthImage& image,
             int frame_bin,
             const std::vector<int>& object_bin,
             Tally* tally) const {
    const bool frame_level = conditions_[c].level == Level::kFrame;
    std::vector<uint8_t> present(conditions_[c].bins.size(), 0);
    for (size_t g = 0; g < image.boxes.size(); ++g) {
      if (image.boxes[g].iscrowd) continue;
      if (object_bin[g] < 0) {
        tally->unrecorded[c] += frame_level ? 0 : 1;
        continue;
      }
      ++tally->objects[c][object_bin[g]];
      present[object_bin[g]] = 1;
    }
    if (frame_level) {
      if (frame_bin >= 0) {
        ++tally->frames[c][frame_bin];
      } else {
        ++tally->unrecorded[c];
      }
      return;
    }
    for (size_t b = 0; b < present.size(); ++b) tally->frames[c][b] += present[b];
  }

  const EvaluationTruth& truth_;
  const std::vector<ConditionBins>& conditions_;
  const Selections& selections_;
  std::vector<int64_t> category_ids_;
  bool with_detections_;
};

StratumMetrics Measure(
    const Accumulation& a, const ConditionBins& c, int bin, int64_t frames, int64_t thin_below) {
  StratumMetrics m;
  m.label = c.bins[bin];
  m.objects = a.ground_truth;
  m.matched_50 = a.matched_50;
  m.false_positives_50 = a.false_positives_50;
  const int m100 = static_cast<int>(kMaxDetections.size()) - 1;
  m.ap = MeanPrecision(a, std::nullopt, m100);
  m.ap50 = MeanPrecision(a, 0, m100);
  m.ar100 = MeanRecall(a, std::nullopt, m100);
  m.recall_50 = m.objects ? static_cast<double>(m.matched_50) / m.objects : 0;
  m.recall_50_ci = WilsonInterval(m.matched_50, m.objects);
  m.thin = m.objects < thin_below;
  m.frames = c.level == Level::kFrame ? a.images : frames;
  return m;
}

std::vector<ConditionMetrics> RankStrata(const std::vector<ConditionBins>& conditions,
                                         const Selections& selections,
                                         std::vector<StratumMetrics> measured) {
  std::vector<ConditionMetrics> out;
  out.reserve(conditions.size());
  for (const ConditionBins& c : conditions)
    out.push_back(ConditionMetrics{c.name, c.description, c.level, {}});
  for (size_t i = 0; i < selections.strata.size(); ++i) {
    if (measured[i].objects > 0 || measured[i].frames > 0)
      out[selections.strata[i].first].strata.push_back(std::move(measured[i]));
  }
  // Worst first; strata without objects (no recall to rank) last.
  for (ConditionMetrics& metrics : out) {
    std::stable_sort(
        metrics.strata.begin(), metrics.strata.end(), [](const auto& x, const auto& y) {
          return std::make_tuple(x.objects == 0, x.recall_50, x.recall_50_ci.high) <
                 std::make_tuple(y.objects == 0, y.recall_50, y.recall_50_ci.high);
        });
  }
  return out;
}

std::vector<ConditionCoverage> CoverageOf(const std::vector<ConditionBins>& conditions,
                                          const Tally& tally,
                                          int64_t thin_below) {
  std::vector<ConditionCoverage> out;
  for (size_t i = 0; i < conditions.size(); ++i) {
    const ConditionBins& c = conditions[i];
    ConditionCoverage coverage{c.name, c.description, c.level, tally.unrecorded[i], {}};
    coverage.cells.resize(c.bins.size());
    for (size_t b = 0; b < c.bins.size(); ++b) {
      CoverageCell& cell = coverage.cells[b];
      cell.label = c.bins[b];
      cell.objects = tally.objects[i][b];
      cell.frames = tally.frames[i][b];
      if (b < c.planned.size()) cell.planned = c.planned[b];
      const int64_t n = c.level == Level::kFrame ? cell.frames : cell.objects;
      cell.flag = n == 0 ? "empty" : n < thin_below ? "thin" : "";
    }
    out.push_back(std::move(coverage));
  }
  return out;
}

}  // namespace

Interval WilsonInterval(int64_t k, int64_t n) {
  if (n <= 0) return {};
  const double p = static_cast<double>(k) / n, z2 = kZ95 * kZ95, nn = static_cast<double>(n);
  const double denominator = 1 + z2 / nn;
  const double centre = (p + z2 / (2 * nn)) / denominator;
  const double half = kZ95 * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn)) / denominator;
  // At 0 or n matches the bound is 0 or 1 exactly (the formula gives it up to rounding).
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

ImageMetrics EvaluateImages(const EvaluationTruth& truth,
                            const std::vector<ConditionBins>& conditions,
                            const std::vector<DetectionBox>* detections,
                            int64_t thin_below) {
  if (detections == nullptr)
    return EvaluateImages(truth, conditions, static_cast<DetectionsByImage*>(nullptr), thin_below);
  DetectionsByImage by_image(std::numeric_limits<uint64_t>::max());
  for (const DetectionBox& d : *detections) by_image.Add(d);
  return EvaluateImages(truth, conditions, &by_image, thin_below);
}

ImageMetrics EvaluateImages(const EvaluationTruth& truth,
                            const std::vector<ConditionBins>& conditions,
                            DetectionsByImage* detections,
                            int64_t thin_below,
                            uint64_t record_memory_bytes) {
  Selections selections;
  for (size_t c = 0; c < conditions.size(); ++c)
    for (int bin = 0; bin < static_cast<int>(conditions[c].bins.size()); ++bin)
      selections.strata.emplace_back(c, bin);
  std::vector<int64_t> category_ids = truth.coco.category_ids;
  std::sort(category_ids.begin(), category_ids.end());
  category_ids.erase(std::unique(category_ids.begin(), category_ids.end()), category_ids.end());
  const size_t K = category_ids.size();
  const ImageEvaluator evaluator(
      truth, conditions, selections, category_ids, detections != nullptr);
  tbb::enumerable_thread_specific<Tally> tallies(
      [&] { return Tally(selections.size(), K, conditions); });

  // The images in batches: read serially (streamed), evaluated in parallel;
  // between batches, the records held go to a sorted run when they take more
  // than their share of memory.
  AccumulationRuns runs(selections.size(), K, record_memory_bytes);
  const auto spill_when_over = [&] {
    size_t held = 0;
    for (const Tally& tally : tallies)
      for (const AccumulationBuilder& builder : tally.builders) held += builder.held_records();
    if (held * sizeof(AccumulationBuilder::Record) <= record_memory_bytes) return;
    std::vector<std::vector<AccumulationBuilder*>> parts(selections.size());
    for (Tally& tally : tallies)
      for (size_t s = 0; s < selections.size(); ++s) parts[s].push_back(&tally.builders[s]);
    runs.Spill(parts);
  };
  std::vector<ImageWork> batch;
  const size_t images_per_batch = ImagesPerBatch(record_memory_bytes);
  uint32_t image_index = 0;
  const auto flush = [&] {
    tbb::parallel_for(
        size_t{0}, batch.size(), [&](size_t i) { evaluator.Evaluate(batch[i], &tallies.local()); });
    batch.clear();
    if (detections != nullptr) spill_when_over();
  };
  truth.ForEachImage([&](TruthImage&& image) {
    ImageWork work;
    work.image_index = image_index++;
    if (detections != nullptr) work.detections = detections->Take(image.image_id);
    work.truth = std::move(image);
    batch.push_back(std::move(work));
    if (batch.size() == images_per_batch) flush();
  });
  flush();
  size_t out_kept = runs.records();
  Tally total(selections.size(), K, conditions);
  std::vector<std::vector<const AccumulationBuilder*>> parts(selections.size());
  for (Tally& tally : tallies) {
    total.AddCounts(tally);
    for (size_t s = 0; s < selections.size(); ++s) {
      parts[s].push_back(&tally.builders[s]);
      out_kept += tally.builders[s].held_records();
    }
  }

  ImageMetrics out;
  out.kept_detections = out_kept;
  out.spilled_runs = runs.runs();
  out.coverage = CoverageOf(conditions, total, thin_below);
  if (detections == nullptr) return out;
  // Every selection's accumulation, all at once (TBB), each into its own slot;
  // a selection's records are freed once it is accumulated.
  std::vector<Accumulation> accumulated(selections.size());
  tbb::parallel_for(size_t{0}, selections.size(), [&](size_t s) {
    accumulated[s] = AccumulationBuilder::Finish(parts[s], &runs, s);
    for (Tally& tally : tallies) tally.builders[s] = AccumulationBuilder(K);
  });
  out.all = accumulated[0];
  out.stats = StatsOf({accumulated[1], accumulated[2], accumulated[3], accumulated[4]});
  std::vector<StratumMetrics> measured(selections.strata.size());
  for (size_t i = 0; i < selections.strata.size(); ++i) {
    const auto [c, bin] = selections.strata[i];
    measured[i] = Measure(accumulated[Selections::kFirstStratum + i],
                          conditions[c],
                          bin,
                          total.frames[c][bin],
                          thin_below);
  }
  out.strata = RankStrata(conditions, selections, std::move(measured));
  return out;
}

}  // namespace lsds::evaluate
