// Algorithm 1 of the paper (section 3.1): where one copy of an object goes. Start from the largest
// box, shrink it by each position constraint in the order written (ON, IN, AROUND, NEAR, BEHIND,
// IN FRONT OF, within), draw a point, turn it to what it FACEs, then resolve what the draw broke:
// a relation, a line of sight (VISIBLE FROM), an overlap (move with retries, delete, hide, allow).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "generator/lang/random.h"
#include "generator/lang/scene.h"
#include "generator/lang/scene/placed_objects.h"

namespace lsds {

// The relations with a reference object and an optional distance (generator/plan/relations.h):
// `NEAR:X`, `NEAR:{X:5}`, `BEHIND:{X:[5,20]}`.
bool IsRelationKey(const std::string& canonical_key);

// What an object says about overlaps: `overlap`, `on_overlap` (move, delete, hide, allow) and
// `retries`.
struct OverlapRules {
  bool overlap = false;
  std::string on_overlap = "move";
  int retries = 100;
};

// The scene around the object being placed.
struct PlacementContext {
  const PlacedObjects& placed;
  const std::string& terrain_symbol;  // ON/IN this is the ground
  const PlannedTerrain& terrain;
  const std::optional<GeoOrigin>& geo;  // where WGS84 positions are (a georeferenced scene)
  Rng& rng;
};

// Places copy `copy` (of `count`) of `def` by its position node `pos` (a null node: no position,
// it stands on the ground). `p` holds the object's class, size and rotation; its centre, bounds,
// support and placement record are set here. Returns false when the copy is deleted
// (on_overlap:delete); a copy that cannot be placed otherwise is an error at `pos`.
bool PlaceObject(const PlacementContext& context,
                 const Definition& def,
                 const Node& pos,
                 int64_t copy,
                 int64_t count,
                 const OverlapRules& rules,
                 Placed* p);

}  // namespace lsds
