// Per-object truth measured on rendered layers: the one definition of the 2D
// box, the visible pixel count, the visibility and the in-frame fraction
// (docs/format.md, "collection.json"). The generator, synth and the
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
#include "libs/geometry/oriented_box2d.h"
#include "libs/geometry/rigid3.h"

namespace lsds {

// What the caller knows of an object besides the layers.
struct ObjectIdentity {
  uint32_t instance_id = 0;
  uint32_t class_id = 0;
  std::string name;
  std::string asset;
  // None for an object its source gives only a 2D box for (an importer's):
  // it then gets an entry only where it has a visible pixel.
  std::optional<OrientedBox> obb;
  // The object's front as a unit direction in the box frame (a column
  // combination of obb.world_from_box), when its kind has one: +x for the
  // generator's vehicles. None for objects with no heading (rocks, barrels,
  // imported objects): their oriented boxes keep the canonical corner order.
  std::optional<Eigen::Vector3d> heading_in_box;
};

// The instanceid layer the masks were measured on: row-major, width x height.
struct IdLayerView {
  const uint32_t* ids = nullptr;
  int width = 0;
  int height = 0;
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
//
// Oriented boxes (docs/format.md, "Oriented boxes"): the visible one is the
// minimum-area rectangle of the object's pixels in `instance_ids` (none when
// it has no pixel or no layer is given), the amodal one that of the projected
// OBB's silhouette points (clipped at the near plane, not to the image). When
// the object has a heading, both put the heading corner first, for the
// heading projected into the image at the OBB centre (canonical order when
// the centre is behind the camera or the heading points along the line of
// sight).
//
// An object without an OBB has no projected or amodal box; its in_frame and
// visibility are not measured and are 1 where it has a visible pixel (docs/
// format.md, "Objects without a 3D box"); a source's own figures replace them.
std::optional<ObjectTruth> MeasureObjectTruth(const ObjectIdentity& object,
                                              const PinholeCamera& camera,
                                              const Rigid3d& cam_from_world,
                                              const IdLayerView& instance_ids,
                                              const InstanceMask* mask,
                                              const UnoccludedCounter& count_unoccluded);

}  // namespace lsds
