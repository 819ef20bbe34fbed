// A re-scatter (`rescatter:true`, docs/languages.md, "Scene changes"): Algorithm 1 again for one
// object on one frame.
#pragma once

#include "generator/lang/capture/change_rules.h"

namespace lsds {

// Places object `o` again in the space its LSCENE constraints left (recorded when it was placed),
// against the objects as they are on frame `f` (its changes so far). Its relations hold on the new
// place: a draw outside NEAR / BEHIND / IN FRONT OF or with a blocked VISIBLE FROM line of sight is
// drawn again; FACING turns it to its point from the new place. Its overlap policy holds: after
// `retries` failing draws it is hidden on this frame (on_overlap delete or hide) or the plan fails
// (move) at `rule`. Sets c's position (and rotation, for FACING; visibility, when hidden).
void Rescatter(const Plan& plan,
               const Rule& rule,
               const PlannedObject& o,
               const PlannedFrame& f,
               Rng& rng,
               ObjectChange* c);

}  // namespace lsds
