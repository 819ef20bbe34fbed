// A camera must be where a drone can be (docs/languages.md, "Cameras where a drone can be"): at
// least the clearance above the terrain under it and outside every rendered object grown by it.
#pragma once

#include <functional>
#include <string>

#include "generator/lang/scene.h"
#include "libs/geometry/rigid3.h"

namespace lsds {

// A violation is a plan error at `where` (the path) naming `pose()` (the path instance, the pose
// and the frame), the camera's place and the terrain height there.
void CheckClearance(const Plan& plan,
                    const PlannedTerrain& ground,
                    double clearance_m,
                    const Rigid3d& cam_from_world,
                    const std::function<std::string()>& pose,
                    const Node& where);

}  // namespace lsds
