// `lsds plan`: LSCENE (+ LCAP) -> the frame plan (docs/languages.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "generator/lang/requirements.h"
#include "generator/lang/source.h"
#include "generator/plan/plan.h"
#include "libs/util/frame_selection.h"

namespace lsds {

// Reads the scene (and the capture) in either notation and samples the plan for
// `seed`. Without a capture file the plan has one default frame (capture.h,
// DefaultCapture: a nadir view over the scene centre). The world depends only
// on `seed`; frame k only on (seed, k), so planning frames k..m alone gives the
// same frames as the full plan. Captures with requirements or quotas need
// `estimator` (generator/estimate.h, MakeFrameEstimatorFactory). Throws lsds::Error naming file and
// place.
Plan MakePlan(const std::filesystem::path& scene,
              const std::optional<std::filesystem::path>& capture,
              uint64_t seed,
              FrameRange frames = {},
              const FrameEstimatorFactory& estimator = {});

// The same from parsed sources (tests, fuzzing, text==JSON comparisons).
Plan MakePlanFromSources(const SourceFile& scene,
                         const SourceFile* capture,
                         uint64_t seed,
                         FrameRange frames = {},
                         const FrameEstimatorFactory& estimator = {});

// The JSON form of a source (what `lsds plan --emit-json` prints), checked
// against lscene.schema.json or lcap.schema.json.
nlohmann::ordered_json SourceToJson(const SourceFile& source);

// Validates a source's JSON tree against its schema (lscene or lcap by the
// start symbol).
void ValidateSourceSchema(const SourceFile& source);

}  // namespace lsds
