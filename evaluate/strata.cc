#include "evaluate/strata.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include <tbb/parallel_for.h>

namespace lsds::evaluate {

namespace {

constexpr double kZ95 = 1.959963984540054;  // the 97.5 % quantile of the normal distribution

// The selection of one bin: the images of a frame condition's bin; for an
// object condition every image, its objects in the bin counted and the others
// ignored, and the unmatched detections of that bin (every one when the
// condition has no value for a detection).
Selection BinSelection(const ConditionBins& c, int bin) {
  Selection s;
  if (c.level == Level::kFrame) {
    s.image = [&c, bin](int64_t image) {
      const auto it = c.image_bin.find(image);
      return it != c.image_bin.end() && it->second == bin;
    };
    return s;
  }
  s.ground_truth = [&c, bin](size_t i) {
    return i < c.object_bin.size() && c.object_bin[i] == bin;
  };
  if (!c.detection_bin.empty())
    s.detection = [&c, bin](size_t i) { return c.detection_bin[i] == bin; };
  return s;
}

StratumMetrics Measure(const CocoEvaluator& evaluator,
                       const ConditionBins& c,
                       int bin,
                       int64_t thin_below) {
  const Accumulation a = evaluator.Accumulate(BinSelection(c, bin));
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
  if (c.level == Level::kFrame) {
    m.frames = a.images;
  } else {
    std::set<int64_t> images;
    const std::vector<GroundTruthBox>& gts = evaluator.data().ground_truth;
    for (size_t i = 0; i < gts.size(); ++i)
      if (i < c.object_bin.size() && c.object_bin[i] == bin && !gts[i].iscrowd)
        images.insert(gts[i].image_id);
    m.frames = static_cast<int64_t>(images.size());
  }
  return m;
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

std::vector<ConditionMetrics> EvaluateStrata(const CocoEvaluator& evaluator,
                                             const std::vector<ConditionBins>& conditions,
                                             int64_t thin_below) {
  // Every stratum is one accumulation over the evaluator's cells, which it
  // only reads: all of them at once (TBB), each into its own slot.
  std::vector<std::pair<size_t, int>> strata;
  for (size_t c = 0; c < conditions.size(); ++c)
    for (int bin = 0; bin < static_cast<int>(conditions[c].bins.size()); ++bin)
      strata.emplace_back(c, bin);
  std::vector<StratumMetrics> measured(strata.size());
  tbb::parallel_for(size_t{0}, strata.size(), [&](size_t i) {
    measured[i] = Measure(evaluator, conditions[strata[i].first], strata[i].second, thin_below);
  });
  std::vector<ConditionMetrics> out;
  out.reserve(conditions.size());
  for (const ConditionBins& c : conditions)
    out.push_back(ConditionMetrics{c.name, c.description, c.level, {}});
  for (size_t i = 0; i < strata.size(); ++i) {
    if (measured[i].objects > 0 || measured[i].frames > 0)
      out[strata[i].first].strata.push_back(std::move(measured[i]));
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

std::vector<ConditionCoverage> Coverage(const EvaluationTruth& truth,
                                        const std::vector<ConditionBins>& conditions,
                                        int64_t thin_below) {
  std::vector<ConditionCoverage> out;
  for (const ConditionBins& c : conditions) {
    ConditionCoverage coverage{c.name, c.description, c.level, 0, {}};
    coverage.cells.resize(c.bins.size());
    std::vector<std::set<int64_t>> frames(c.bins.size());
    for (size_t i = 0; i < c.object_bin.size(); ++i) {
      const GroundTruthBox& g = truth.coco.ground_truth[i];
      if (g.iscrowd) continue;
      if (c.object_bin[i] < 0) {
        coverage.unrecorded += c.level == Level::kObject;
        continue;
      }
      ++coverage.cells[c.object_bin[i]].objects;
      frames[c.object_bin[i]].insert(g.image_id);
    }
    if (c.level == Level::kFrame) {
      for (auto& f : frames) f.clear();
      for (const auto& [image, bin] : c.image_bin) frames[bin].insert(image);
      coverage.unrecorded = static_cast<int64_t>(truth.coco.image_ids.size() - c.image_bin.size());
    }
    for (size_t b = 0; b < c.bins.size(); ++b) {
      CoverageCell& cell = coverage.cells[b];
      cell.label = c.bins[b];
      cell.frames = static_cast<int64_t>(frames[b].size());
      const int64_t n = c.level == Level::kFrame ? cell.frames : cell.objects;
      cell.flag = n == 0 ? "empty" : n < thin_below ? "thin" : "";
    }
    out.push_back(std::move(coverage));
  }
  return out;
}

}  // namespace lsds::evaluate
