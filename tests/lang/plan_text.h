// LSCENE/LCAP text to a plan, for the language and generator tests: the scene
// parsed as "s.lscene", the capture as "c.lcap", so that error messages name
// those files.
#pragma once

#include <cstdint>
#include <string>

#include "generator/lang/planner.h"
#include "generator/lang/source.h"
#include "libs/util/error.h"

namespace lsds::testing {

inline Plan PlanText(const std::string& scene,
                     const std::string& capture,
                     uint64_t seed = 1,
                     FrameRange frames = {},
                     const FrameEstimatorFactory& estimator = {}) {
  const SourceFile s = ParseSource(scene, "s.lscene", false);
  const SourceFile c = ParseSource(capture, "c.lcap", false);
  return MakePlanFromSources(s, &c, seed, frames, estimator);
}

// The error message (with its location) of parsing and planning `scene` and
// `capture` (none when empty); "" when they plan.
inline std::string PlanErrorOf(const std::string& scene, const std::string& capture = "") {
  try {
    const SourceFile s = ParseSource(scene, "s.lscene", false);
    if (capture.empty()) {
      MakePlanFromSources(s, nullptr, 1);
    } else {
      const SourceFile c = ParseSource(capture, "c.lcap", false);
      MakePlanFromSources(s, &c, 1);
    }
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace lsds::testing
