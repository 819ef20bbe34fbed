// The check of an LSCENE program before anything is drawn: every definition's keys, references
// (undefined, forward, self, of the wrong kind), classes and the start rule. What the check learns
// on the way is what evaluation needs: the terrain's symbol, the class aliases and asset library,
// and how many copies the start rule asks of each object.
#pragma once

#include <map>
#include <set>
#include <string>

#include "generator/lang/scene.h"
#include "generator/lang/scene/class_catalog.h"

namespace lsds {

struct SceneSymbols {
  std::string terrain;                       // the terrain's symbol ("" without one)
  std::map<std::string, Node> start_counts;  // object -> the start rule's count (null: one)
  std::set<std::string> many_without_count;  // MANY(X) without a count: 5 to 15 copies
};

// Checks `scene` (the first error is thrown, located) and fills `assets` with its aliases and
// library.
SceneSymbols CheckScene(const Program& scene, ClassCatalog* assets);

}  // namespace lsds
