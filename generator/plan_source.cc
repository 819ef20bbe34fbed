#include "generator/plan_source.h"

#include <limits>

#include "generator/estimate.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "libs/collection/json_stream.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"

namespace lsds::gen {

Plan PlanFromScene(const std::string& scene,
                   const std::string& capture,
                   uint64_t seed,
                   int64_t first_frame,
                   int64_t last_frame) {
  std::optional<std::filesystem::path> capture_path;
  if (!capture.empty()) capture_path = capture;
  // Frames are planned independently of each other (frame k depends on (seed,
  // k) only), so planning just the requested range gives the same frames as the
  // full plan.
  FrameRange range;
  range.begin = first_frame;
  range.end = last_frame == std::numeric_limits<int64_t>::max() ? -1 : last_frame;
  return MakePlan(scene, capture_path, seed, range, MakeFrameEstimatorFactory());
}

Plan LoadPlanJson(const std::string& path) { return PlanFromJson(ReadJsonFile(path), path); }

}  // namespace lsds::gen
