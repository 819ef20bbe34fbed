// LSCENE: the definitions of a scene file and their evaluation into the world state of a plan
// (sky, sun, atmosphere, skylight, terrain, objects). The evaluator's units are in scene/: the
// check, the class table, the assets, the ground, the placed objects and Algorithm 1 (position).
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "generator/lang/source.h"
#include "generator/lang/values.h"
#include "generator/plan/plan.h"

namespace lsds {

// One "NAME = kind{...}" statement.
struct Definition {
  std::string symbol;
  std::string kind;  // canonical kind: skybox, light, atmosphere, skylight, terrain,
                     // object, classes, camera, path, collection, scene_change
  Node body;
  Node statement;    // the whole "NAME: {kind: body}" node, for messages
  size_t order = 0;  // position in the file
};

// Splits a source into its start rule and definitions, checking kinds
// (did-you-mean) and names. `start` is "LSCENE" or "LCAP".
struct Program {
  const SourceFile* src = nullptr;
  std::string start;
  Node start_rule;  // may be null: then every definition counts once
  std::vector<Definition> definitions;
  const Definition* Find(const std::string& symbol) const;
};
Program ReadProgram(const SourceFile& src, const std::string& start);

// Table 1 category symbols usable in a start rule for "all definitions of that
// kind".
const std::map<std::string, std::string>& CategoryKinds();

// Built-in procedural classes the renderer supports and their default extents
// (metres).
const std::map<std::string, Eigen::Vector3d>& BuiltinClasses();

// An LCAP target's label (docs/languages.md, "Class names"): none (its classes come from the
// scene), one id (`O1:5`: the paper's per-pixel label, whatever class the symbol draws), or one id
// per class it draws (`V1:{car:1,truck:2}`), which keeps the classes apart.
struct TargetLabel {
  uint32_t first_id = 0;
  std::map<std::string, uint32_t> by_class;
  Node where;  // the label in the capture, for messages
  bool labelled() const { return first_id != 0 || !by_class.empty(); }
  bool operator==(const TargetLabel& o) const {
    return first_id == o.first_id && by_class == o.by_class;
  }
};
// LCAP targets by symbol.
using TargetLabels = std::map<std::string, TargetLabel>;

// Checks every key of every definition (unknown keys, undefined or forward
// references, unknown classes) without sampling, then samples the world state
// from the world stream of `seed`. Fills plan->classes, sky, sun, fog_density,
// skylight_intensity, terrain and objects. `targets` (may be empty): objects
// whose symbol is listed are the targets and their class id is the given label.
void EvaluateScene(const Program& scene, uint64_t seed, const TargetLabels& targets, Plan* plan);

// A class option as the scene resolves it (scene/class_catalog.h): the asset drawn (a built-in
// class or a mesh path relative to the scene file) and the class name it is labelled with (a
// classes{} alias keeps the user's name).
struct SceneClass {
  std::string asset;
  std::string name;
};

// Removes from the class table the classes that no rendered object can show:
// classes whose objects are all invisible helpers, unless a capture change may
// make one visible (`symbols_made_visible`). Their objects get class id 0.
// The terrain class stays. A clean collection then has no unused class.
// `extra_shown`: class ids a capture swaps in (class changes).
void DropHelperClasses(const std::set<std::string>& symbols_made_visible,
                       Plan* plan,
                       const std::set<uint32_t>& extra_shown = {});

}  // namespace lsds
