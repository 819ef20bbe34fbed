// Where `lsds generate` gets its plan: LSCENE/LCAP through the planner
// (generator/lang), or a plan JSON file. Kept apart so the renderer builds
// without the language front end.
#pragma once

#include <cstdint>
#include <string>

#include "generator/plan/plan.h"

namespace lsds::gen {

// Expands SCENE (and CAPTURE, may be empty) with `seed`, frames [first, last).
// Throws lsds::Error when the language front end is not part of this build.
Plan PlanFromScene(const std::string& scene,
                   const std::string& capture,
                   uint64_t seed,
                   int64_t first_frame,
                   int64_t last_frame);
// Reads a plan JSON file (schemas/plan.schema.json).
Plan LoadPlanJson(const std::string& path);

}  // namespace lsds::gen
