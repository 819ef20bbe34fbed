// Scene changes keep the LSCENE placement (docs/languages.md, "Scene changes keep the placement"):
// an object ON a support stays on it, what stands on a moved object rides with it, and an object
// that may not overlap does not.
#pragma once

#include <vector>

#include "generator/lang/capture/change_rules.h"

namespace lsds {

// Applies the placement to frame `f`, whose changes so far came from `change_rules` (one rule per
// change, in order). A change of size, rotation or offset re-applies the object's placement: an
// object ON a support keeps its base on the support's top (on the terrain: the height under its
// new centre, as Algorithm 1 places it), objects standing ON (or placed IN) it ride with it, and
// an object that may not overlap must not overlap another after the change. The re-seated and
// carried poses are appended as changes of the frame; an overlap is a plan error at the change
// that caused it. On a frame whose terrain shape was changed (by `ground_rule`, else null), every
// object standing ON the terrain is re-seated on the frame's ground: its z moves by the change of
// the ground's height under it (docs/languages.md, "Terrain shape changes").
void KeepPlacement(const Plan& plan,
                   const std::vector<const Rule*>& change_rules,
                   PlannedFrame* f,
                   const Rule* ground_rule = nullptr);

}  // namespace lsds
