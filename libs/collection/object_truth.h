// Per-object truth measured on rendered layers: the one definition of the 2D
// box, the visible pixel count, the visibility and the in-frame fraction
// (docs/format.md, "collection.json"). The generator, libs/synth and the
// importers all call these, so the definitions cannot drift apart.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_map>
#include <vector>

#include "libs/collection/model.h"
#include "libs/geometry/box2d.h"
#include "libs/geometry/camera.h"
#include "libs/geometry/instance_mask.h"  // MeasureInstanceMasks: the box of a mask
#include "libs/geometry/oriented_box.h"
#include "libs/geometry/rigid3.h"

namespace lsds {

// What the caller knows of an object besides the layers.
struct ObjectIdentity {
  uint32_t instance_id = 0;
  uint32_t class_id = 0;
  std::string name;
  std::string asset;
  OrientedBox obb;
};

// Counts the pixels inside `bounds` (clipped to the image) that the object
// would cover with no occluder, at the same sample positions as the id layer.
using UnoccludedCounter = std::function<int64_t(const Box2d& bounds)>;

// The truth entry of one object in one frame, or nullopt when the object is
// nowhere near the image (its projected OBB misses the image and it has no
// pixel). Visibility = visible pixels / max(unoccluded pixels, visible pixels):
// the max keeps it in [0, 1] where a sample position differs by a hair between
// the two passes. `count_unoccluded` may be empty when the caller cannot
// count; the visibility is then 1 for a visible object and 0 otherwise.
std::optional<ObjectTruth> MeasureObjectTruth(const ObjectIdentity& object,
                                              const PinholeCamera& camera,
                                              const Rigid3d& cam_from_world,
                                              const InstanceMask* mask,
                                              const UnoccludedCounter& count_unoccluded);

}  // namespace lsds
