// Post-process materials (LCAP `PPMaterial:[...]`, docs/generator.md
// "Post-process materials"): sensor and lens effects applied to the rendered
// RGB only, after the truth layers are final. Truth (ids, depth, normals, world
// position, shadow, motion, bundle) is never touched, so a frame's truth is byte
// for byte the same with and without them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "generator/plan/plan.h"
#include "generator/render/film.h"

namespace lsds::gen {

// The known effects, canonical names.
const std::vector<std::string>& PostProcessNames();
// The canonical name of `name` (case and '_'/'-'/' ' ignored; aliases such as
// Defocus = EdgeBlur), or "" when unknown.
std::string CanonicalPostProcess(const std::string& name);
// Messages for the names that are not effects ("did you mean"); such names
// stay recorded in the provenance and are not applied.
std::vector<std::string> UnknownPostProcess(const std::vector<std::string>& names);

// Applies `names` in order to the film's rgb layer. Deterministic: noise draws
// depend only on (seed, frame, pixel). `lens`: the aperture, focus and sensor
// width DepthOfField uses. Returns the distance DepthOfField focused at, if it
// ran.
std::optional<double> ApplyPostProcess(const std::vector<std::string>& names,
                                       uint64_t seed,
                                       const PlannedFrame& frame,
                                       const PlannedExposure& lens,
                                       Film* film);

}  // namespace lsds::gen
