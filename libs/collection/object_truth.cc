#include "libs/collection/object_truth.h"

#include <algorithm>

namespace lsds {

std::optional<ObjectTruth> MeasureObjectTruth(const ObjectIdentity& object,
                                              const PinholeCamera& camera,
                                              const Rigid3d& cam_from_world,
                                              const InstanceMask* mask,
                                              const UnoccludedCounter& count_unoccluded) {
  ObjectTruth t;
  t.instance_id = object.instance_id;
  t.class_id = object.class_id;
  t.name = object.name;
  t.asset = object.asset;
  t.obb = object.obb;
  if (mask != nullptr && mask->pixels > 0) {
    t.visible_pixels = mask->pixels;
    t.bbox = mask->box;
  }
  if (const std::optional<Box2d> projected = ProjectedBounds(t.obb, camera, cam_from_world)) {
    const Box2d clipped = projected->ClippedTo(camera.width, camera.height);
    if (!clipped.empty()) t.bbox_projected = clipped;
  }
  if (!t.bbox_projected && t.visible_pixels == 0) return std::nullopt;
  t.in_frame = InFrameFraction(t.obb, camera, cam_from_world);
  int64_t unoccluded = t.visible_pixels;
  if (t.bbox_projected && count_unoccluded)
    unoccluded = std::max(unoccluded, count_unoccluded(*t.bbox_projected));
  t.visibility = unoccluded > 0 ? static_cast<double>(t.visible_pixels) / unoccluded : 0.0;
  return t;
}

}  // namespace lsds
