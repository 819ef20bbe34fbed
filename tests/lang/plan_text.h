// LSCENE/LCAP text to a plan, for the language and generator tests: the scene
// parsed as "s.lscene", the capture as "c.lcap", so that error messages name
// those files.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "generator/lang/planner.h"
#include "generator/lang/source.h"
#include "generator/plan/plan_json.h"
#include "libs/util/error.h"

namespace lsds::testing {

// With LSDS_RECORD_PLANS=DIR, every plan (or planning error) these helpers make is written to
// DIR/<digest of the inputs>.txt, so that a change meant to keep plans byte for byte (a refactor
// of the evaluators) can be checked on every test input: record before, record after, diff -r.
inline void RecordPlan(const std::string& scene,
                       const std::string& capture,
                       uint64_t seed,
                       const FrameRange& frames,
                       const std::string& outcome) {
  const char* dir = std::getenv("LSDS_RECORD_PLANS");
  if (!dir || !*dir) return;
  uint64_t h = 1469598103934665603ull;  // FNV-1a over the inputs
  auto mix = [&h](const std::string& bytes) {
    for (const unsigned char ch : bytes + '\0') h = (h ^ ch) * 1099511628211ull;
  };
  mix(scene);
  mix(capture);
  mix(std::to_string(seed) + ":" + std::to_string(frames.begin) + ":" + std::to_string(frames.end));
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.txt", static_cast<unsigned long long>(h));
  std::ofstream(std::string(dir) + "/" + name) << outcome;
}

inline Plan PlanText(const std::string& scene,
                     const std::string& capture,
                     uint64_t seed = 1,
                     FrameRange frames = {},
                     const FrameEstimatorFactory& estimator = {}) {
  try {
    const SourceFile s = ParseSource(scene, "s.lscene", false);
    Plan plan;
    if (capture.empty()) {  // no capture: the default one
      plan = MakePlanFromSources(s, nullptr, seed, frames, estimator);
    } else {
      const SourceFile c = ParseSource(capture, "c.lcap", false);
      plan = MakePlanFromSources(s, &c, seed, frames, estimator);
    }
    RecordPlan(scene, capture, seed, frames, PlanToJson(plan).dump(1));
    return plan;
  } catch (const Error& e) {
    RecordPlan(scene, capture, seed, frames, std::string("error: ") + e.what());
    throw;
  }
}

// The message of the lsds::Error `f` throws; "" when it throws none.
template <typename F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The error message (with its location) of parsing and planning `scene` and
// `capture` (none when empty); "" when they plan.
inline std::string PlanErrorOf(const std::string& scene, const std::string& capture = "") {
  try {
    const SourceFile s = ParseSource(scene, "s.lscene", false);
    Plan plan;
    if (capture.empty()) {
      plan = MakePlanFromSources(s, nullptr, 1);
    } else {
      const SourceFile c = ParseSource(capture, "c.lcap", false);
      plan = MakePlanFromSources(s, &c, 1);
    }
    RecordPlan(scene, capture, 1, {}, PlanToJson(plan).dump(1));
  } catch (const Error& e) {
    RecordPlan(scene, capture, 1, {}, std::string("error: ") + e.what());
    return e.what();
  }
  return "";
}

}  // namespace lsds::testing
