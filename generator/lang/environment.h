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

// The light values of a `kind` block that no daylight has (docs/languages.md, "Light units"), each
// a message located at `body`: a sun under 100 lux more than 10 degrees up (a value of the old
// unitless scale?), a sun over 150000 lux (above the solar constant), a sky over 60000 lux or
// 30000 cd/m^2. Values kept; nothing for blocks that set no light.
std::vector<std::string> ImplausibleLight(const std::string& kind,
                                          const Node& body,
                                          const PlannedEnvironment& environment);

// A sun given by date and time (`clock_utc_s`) gets the solar position of
// `geo` at `time_s` seconds after capture time 0; otherwise nothing changes.
void PlaceSun(const GeoOrigin& geo, double time_s, PlannedSun* sun);

}  // namespace lsds
