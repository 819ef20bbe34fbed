// The capture camera's targets (`targets:[O1:5, O2]`, docs/languages.md, "Targets"): the scene
// objects the capture is about, with the label id each is recorded with.
#pragma once

#include <string>

#include "generator/lang/scene.h"

namespace lsds {

// The targets named by the capture's camera, checked against the scene: `[O1:5, V1:{car:1,
// truck:2}, O2]` (a target listed without a label, O2, keeps its classes from the scene).
TargetLabels ReadTargets(const Program& capture, const Program& scene);

// The symbol of the camera's first target (what a hemi without a centre circles); "" when none.
std::string FirstTarget(const Program& capture);

}  // namespace lsds
