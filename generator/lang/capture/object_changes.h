// An object's scene change on one frame (docs/languages.md, "Scene changes"): the values its
// rule's keys draw (material, rotation, visibility, extent, scale, offset, class), and the pose
// and velocity of an object moving along its paths.
#pragma once

#include <cstdint>

#include "generator/lang/capture/change_rules.h"
#include "generator/lang/capture/class_swaps.h"
#include "generator/lang/requirements.h"

namespace lsds {

// The change `rule` draws for object `o` from `rng`. A class change under a class quota with
// importance sampling draws the option of the frame's bin (`demand`, may be null).
ObjectChange DrawObjectChange(const Rule& rule,
                              const PlannedObject& o,
                              Rng& rng,
                              const FrameDemand* demand,
                              ClassSwaps* swaps);

// An object moving along its rule's legs (docs/languages.md, "Objects that move"), on time step
// `k` at `fps`: at time t since the rule began it is where its path is after t * speed metres;
// after the last leg it stays at its end, at rest. Several copies of a symbol move in formation:
// each keeps its planned offset from the first copy. Its velocity is the path's; an object
// standing on the terrain follows the ground, so the vertical component is the terrain's slope
// along the motion (its z is re-seated on the support by KeepPlacement). Sets c's position,
// velocity and, with `heading`, its rotation.
void MoveAlongLegs(const Rule& rule,
                   const PlannedObject& o,
                   const Plan& plan,
                   const PlannedTerrain& ground,
                   int64_t k,
                   double fps,
                   ObjectChange* c);

}  // namespace lsds
