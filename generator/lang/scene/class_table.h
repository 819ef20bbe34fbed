// The scene's class table (docs/languages.md, "Class names"): which id each class an object may
// draw takes, the ids of the capture's labelled targets, and the id of a drawn object.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "generator/lang/scene.h"
#include "generator/lang/scene/class_catalog.h"

namespace lsds {

// A labelled target's ids by the class names it may draw: `O1:5` labels all of them 5 (the paper's
// per-pixel label of the target), `V1:{car:1,truck:2}` each as it lists them (every class it draws
// listed, no other: else an error at the label).
using LabelIds = std::map<std::string, uint32_t>;
LabelIds LabelIdsOf(const Program& scene,
                    const ClassCatalog& catalog,
                    const std::string& symbol,
                    const TargetLabel& label);

// The labelled targets' ids, by symbol.
using TargetClassIds = std::map<std::string, LabelIds>;

// Fills plan->classes: each label id, named after the classes it labels joined by "|" ("#id" added
// when another class has that name); then, skipping those ids, the other objects' classes in
// order of first appearance in the file, the terrain's first. Returns the labelled targets' ids.
TargetClassIds AssignClassIds(const Program& scene,
                              const ClassCatalog& assets,
                              const TargetLabels& targets,
                              Plan* plan);

// The class id of an object of `symbol` that drew the class `class_name`: its label's id for that
// class if it is a labelled target, else the table's id of that name (0 when none).
uint32_t ClassIdOf(const Plan& plan,
                   const TargetClassIds& labelled,
                   const std::string& symbol,
                   const std::string& class_name);

}  // namespace lsds
