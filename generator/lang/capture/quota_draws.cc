#include "generator/lang/capture/quota_draws.h"

#include <cmath>
#include <limits>
#include <string>

#include "generator/lang/random.h"

namespace lsds {

std::optional<std::pair<double, double>> DemandedBin(const FrameDemand* demand,
                                                     const std::string& quantity,
                                                     const PlannedObject* object) {
  if (!demand) return std::nullopt;
  for (const auto& [q, bin] : demand->bins) {
    if (!q->importance || q->quantity != quantity) continue;
    if (object && !(q->target == object->symbol || (q->target.empty() && object->target))) continue;
    auto range = BinRange(*q, bin);
    // A bin other than the last excludes its upper edge.
    if (!q->categorical() && bin + 2 < static_cast<int>(q->edges.size()))
      range.second = std::nextafter(range.second, -std::numeric_limits<double>::infinity());
    return range;
  }
  return std::nullopt;
}

uint64_t RedrawSeed(uint64_t seed, int attempt) {
  return attempt == 0 ? seed
                      : MixKey(MixKey(seed, static_cast<uint64_t>(StreamTag::kRedraw)),
                               static_cast<uint64_t>(attempt));
}

double QuotaDraws::Measure(const FrameDemand& demand,
                           const std::vector<PlannedFrame>& frames,
                           std::vector<FrameMeasure>* measures) {
  double violation = 0;
  for (size_t c = 0; c < frames.size(); ++c) {
    FrameMeasure m = estimator_(plan_, frames[c]);
    m.frame = FrameMeasures(plan_, frames[c]);
    const double v = Violation(demand, m);
    violation = c == 0 ? v : requirements_.rig_any ? std::min(violation, v) : violation + v;
    measures->push_back(std::move(m));
  }
  return violation;
}

std::vector<PlannedFrame> QuotaDraws::Step(int64_t step,
                                           const FrameDemand& demand,
                                           const Draw& draw) {
  if (demand.active.empty() && demand.bins.empty()) return draw(0, nullptr);
  if (!estimator_) {
    if (!factory_)
      throw Error(
          "this capture has requirements or quotas, which need the generator's estimator "
          "(lsds plan / lsds generate)");
    estimator_ = factory_();
  }
  std::vector<PlannedFrame> best;
  std::vector<FrameMeasure> best_measures;
  double best_violation = 0;
  int attempts = 0;
  std::optional<Error> unplaceable;  // a draw the camera cannot take (clearance)
  for (int attempt = 0; attempt <= requirements_.budget; ++attempt) {
    std::vector<PlannedFrame> frames;
    try {
      frames = draw(attempt, &demand);
    } catch (const Error& e) {
      // A draw where the drone cannot be is rejected like one that misses the requirements; only
      // when every draw is, the error stands.
      ++attempts;
      if (!unplaceable) unplaceable = e;
      continue;
    }
    std::vector<FrameMeasure> measures;
    const double violation = Measure(demand, frames, &measures);
    ++attempts;
    if (best.empty() || violation < best_violation) {
      best = std::move(frames);
      best_measures = std::move(measures);
      best_violation = violation;
    }
    if (violation == 0) break;
  }
  if (best.empty()) throw *unplaceable;
  for (size_t c = 0; c < best.size(); ++c) {
    PlannedFrame& f = best[c];
    f.requirements = DemandRecord(demand, best_measures[c]);
    (*f.requirements)["attempts"] = attempts;
    if (plan_.rig) {
      // The step is the unit: the report counts it once.
      (*f.requirements)["step"] = step;
      (*f.requirements)["step_met"] = best_violation == 0;
    }
  }
  if (best_violation > 0 && requirements_.fail_on_budget)
    FailBudget(step, best.size(), attempts, best.front());
  return best;
}

void QuotaDraws::FailBudget(int64_t step,
                            size_t cameras,
                            int attempts,
                            const PlannedFrame& closest) const {
  const int64_t n = static_cast<int64_t>(cameras);
  throw Error((plan_.rig ? "step " + std::to_string(step) + " (frames " + std::to_string(step * n) +
                               "-" + std::to_string(step * n + n - 1) + ")"
                         : "frame " + std::to_string(step)) +
                  ": no draw met the requirements in " + std::to_string(attempts) +
                  " attempts (budget " + std::to_string(requirements_.budget) +
                  "): " + closest.requirements->at("checks").dump(),
              where_);
}

}  // namespace lsds
