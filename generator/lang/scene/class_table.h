// The scene's class table (docs/languages.md, "Class names"): which id each class an object may
// draw takes, and the id of a drawn object.
#pragma once

#include <cstdint>
#include <string>

#include "generator/lang/scene.h"
#include "generator/lang/scene/scene_assets.h"

namespace lsds {

// Ids in order of first appearance in the file, the terrain's first, skipping the ids the capture's
// targets take as labels. A labelled target's class is named after what it draws: the class names
// of its options joined by "|" ("#label" added when another class has that name).
void AssignClassIds(const Program& scene,
                    const SceneAssets& assets,
                    const TargetLabels& targets,
                    Plan* plan);

// The class id of an object of `symbol` that drew the class `class_name`: its target label if it
// has one, else the table's id of that name (0 when none).
uint32_t ClassIdOf(const Plan& plan,
                   const TargetLabels& targets,
                   const std::string& symbol,
                   const std::string& class_name);

}  // namespace lsds
