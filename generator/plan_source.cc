#include "generator/plan_source.h"

#include "libs/util/error.h"

namespace lsds::gen {

Plan PlanFromScene(const std::string& scene, const std::string&, uint64_t, int64_t, int64_t) {
  throw Error("LSCENE/LCAP expansion is not available in this build yet (generator/lang); use --plan "
              "plan.json or --demo",
              Location(scene));
}

Plan LoadPlanJson(const std::string& path) {
  throw Error("plan JSON reading is not available in this build yet (generator/plan/plan_json)",
              Location(path));
}

}  // namespace lsds::gen
