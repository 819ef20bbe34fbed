// LSCENE's environment functions - sky, light, atmosphere, skylight and the
// terrain's material - in one place, used by LSCENE definitions and by LCAP
// scene changes ("any and all LSCENE functions are callable here", the
// paper's section 3.2).
#pragma once

#include <string>
#include <vector>

#include "generator/lang/random.h"
#include "generator/lang/values.h"
#include "generator/plan/plan.h"

namespace lsds {

// skybox, light, atmosphere, skylight (terrain: its material only).
bool IsEnvironmentKind(const std::string& kind);

// The keys a definition of `kind` accepts (vocabulary.h); `in_change` for an
// LCAP change (a terrain's shape cannot change, only its material).
std::vector<std::string> EnvironmentKeys(const std::string& kind, bool in_change);

// Samples the keys of `body` (a definition or change of `kind`) into
// `environment`, with located errors for bad values.
void ApplyEnvironment(const std::string& kind,
                      const Node& body,
                      Rng& rng,
                      PlannedEnvironment* environment);

// A sun given by date and time (`clock_utc_s`) gets the solar position of
// `geo` at `time_s` seconds after capture time 0; otherwise nothing changes.
void PlaceSun(const GeoOrigin& geo, double time_s, PlannedSun* sun);

}  // namespace lsds
