// Requirements and quotas met by redrawing (docs/languages.md, "Requirements and quotas"): a time
// step's frames are drawn again until the estimate meets the step's demand, within the budget;
// importance sampling draws a quota's free variable within the frame's bin directly.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "generator/lang/requirements.h"
#include "libs/util/error.h"

namespace lsds {

// The bin [lo, hi] the frame being drawn must hit in a quota over `quantity` with
// sampling:importance, if any (none without a demand). For a target quantity, only a quota on
// `object`'s symbol (or, for class, on every target) counts. Depends only on the frame's demand,
// so draws stay functions of (seed, frame, frame count).
std::optional<std::pair<double, double>> DemandedBin(const FrameDemand* demand,
                                                     const std::string& quantity,
                                                     const PlannedObject* object = nullptr);

// The seed of draw number `attempt` of a frame: the first draws from the frame's own streams,
// redraws from streams of (seed, redraw, attempt), so that every draw still depends only on the
// seed and the frame.
uint64_t RedrawSeed(uint64_t seed, int attempt);

class QuotaDraws {
 public:
  // `where` locates a plan error (on_budget:fail); `estimator` makes the estimator on first use.
  QuotaDraws(const RequirementSet& requirements,
             const FrameEstimatorFactory& estimator,
             const Plan& plan,
             Location where)
      : requirements_(requirements), factory_(estimator), plan_(plan), where_(std::move(where)) {}

  // The frames of one time step for draw number `attempt` under `demand` (null: no demand).
  using Draw = std::function<std::vector<PlannedFrame>(int attempt, const FrameDemand* demand)>;

  // The frames of time step `step` (one per rig camera; the frame itself without a rig), drawn
  // until the estimate meets `demand` in every camera (or, with cameras:any, in one), within the
  // budget; else the draw that came closest (the smallest violation: summed over the cameras, or
  // the least of them with cameras:any). Each frame records its demand, measures and attempts.
  std::vector<PlannedFrame> Step(int64_t step, const FrameDemand& demand, const Draw& draw);

 private:
  // The frames' estimates and the step's violation.
  double Measure(const FrameDemand& demand,
                 const std::vector<PlannedFrame>& frames,
                 std::vector<FrameMeasure>* measures);
  [[noreturn]] void FailBudget(int64_t step,
                               size_t cameras,
                               int attempts,
                               const PlannedFrame& closest) const;

  const RequirementSet& requirements_;
  FrameEstimatorFactory factory_;
  const Plan& plan_;
  Location where_;
  FrameEstimator estimator_;
};

}  // namespace lsds
