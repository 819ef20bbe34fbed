#include "generator/plan_source.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "generator/estimate.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"

namespace lsds::gen {

namespace {

// A selection the user gave (an empty text is every frame, unchecked).
bool Given(const FrameSelection& frames) { return !frames.text.empty(); }

Plan PlanRange(const std::string& scene,
               const std::string& capture,
               uint64_t seed,
               const FrameRange& range) {
  std::optional<std::filesystem::path> capture_path;
  if (!capture.empty()) capture_path = capture;
  return MakePlan(scene, capture_path, seed, range, MakeFrameEstimatorFactory());
}

}  // namespace

Plan PlanFromScene(const std::string& scene,
                   const std::string& capture,
                   uint64_t seed,
                   const FrameSelection& frames) {
  Plan plan = PlanRange(scene, capture, seed, frames);
  if (!Given(frames)) return plan;
  // The restricted plan holds exactly the selected frames that exist; anything
  // less means the selection reaches past the plan (the full plan is only made
  // to say so).
  const bool complete = frames.bounded()
                            ? static_cast<int64_t>(plan.frames.size()) == frames.end - frames.begin
                            : !plan.frames.empty();
  if (!complete) CheckPlanFrames(frames, PlanRange(scene, capture, seed, FrameRange{}));
  return plan;
}

void CheckPlanFrames(const FrameSelection& frames, const Plan& plan) {
  std::vector<int64_t> indices;
  indices.reserve(plan.frames.size());
  for (const PlannedFrame& frame : plan.frames) indices.push_back(frame.index);
  std::sort(indices.begin(), indices.end());
  CheckFrameSelection(frames, indices, "the plan");
}

Plan LoadPlanJson(const std::string& path) { return PlanFromJson(ReadJsonFile(path), path); }

Plan PlanForRendering(const PlanRequest& request) {
  const int sources = (request.demo ? 1 : 0) + (request.plan_file.empty() ? 0 : 1) +
                      (request.scene.empty() ? 0 : 1);
  if (sources != 1) throw Error("give exactly one of SCENE [CAPTURE], --plan FILE or --demo");
  Plan plan;
  if (request.demo) {
    DemoOptions demo = *request.demo;
    demo.seed = request.seed.value_or(0);
    plan = MakeDemoPlan(demo);
  } else if (!request.plan_file.empty()) {
    plan = LoadPlanJson(request.plan_file);
    if (request.seed) plan.seed = *request.seed;
  } else {
    // The frame before the first selected one is planned too (not rendered):
    // the first frame's motion is measured against it.
    const uint64_t seed = request.seed.value_or(0);
    FrameSelection planned = request.frames;
    if (Given(planned) && planned.begin > 0) --planned.begin;
    plan = PlanFromScene(request.scene, request.capture, seed, planned);
    // In a rig the frame before in the same camera is one time step back.
    if (Given(planned) && plan.rig && plan.rig->cameras.size() > 1 && planned.begin > 0) {
      const int64_t n = static_cast<int64_t>(plan.rig->cameras.size());
      planned.begin = std::max<int64_t>(0, request.frames.begin - n);
      plan = PlanFromScene(request.scene, request.capture, seed, planned);
    }
  }
  // Before any output is touched: an out-of-range --frames never empties (or,
  // with --force, wipes) an existing collection.
  if (Given(request.frames)) CheckPlanFrames(request.frames, plan);
  return plan;
}

}  // namespace lsds::gen
