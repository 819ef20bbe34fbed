#include "libs/collection/object_truth.h"

#include <algorithm>

namespace lsds {

namespace {

// The direction in the image of a step along `direction_in_world` from
// `point_in_world` (the derivative of the projection, up to a positive
// factor); nullopt when the point is not in front of the camera or the
// direction is within 1e-6 rad of its line of sight, where the image shows no
// front.
std::optional<Eigen::Vector2d> ImageDirectionAt(const PinholeCamera& camera,
                                                const Rigid3d& cam_from_world,
                                                const Eigen::Vector3d& point_in_world,
                                                const Eigen::Vector3d& direction_in_world) {
  const Eigen::Vector3d p = cam_from_world * point_in_world;
  const Eigen::Vector3d d = cam_from_world.rotation * direction_in_world;
  if (!(p.z() > 0) || p.cross(d).norm() <= 1e-6 * p.norm() * d.norm()) return std::nullopt;
  // z * d/dt of (fx x / z, fy y / z) along p + t d.
  return Eigen::Vector2d(camera.fx * (d.x() - p.x() * d.z() / p.z()),
                         camera.fy * (d.y() - p.y() * d.z() / p.z()));
}

}  // namespace

std::optional<ObjectTruth> MeasureObjectTruth(const ObjectIdentity& object,
                                              const PinholeCamera& camera,
                                              const Rigid3d& cam_from_world,
                                              const IdLayerView& instance_ids,
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
    if (instance_ids.ids != nullptr) {
      t.bbox_oriented = MaskOrientedBox(
          instance_ids.ids, instance_ids.width, instance_ids.height, t.instance_id, mask->box);
    }
  }
  if (!t.obb) {
    // Nothing says how much of it is hidden or outside the image: not measured.
    if (t.visible_pixels == 0) return std::nullopt;
    t.in_frame = 1;
    t.visibility = 1;
    return t;
  }
  const OrientedBox& obb = *t.obb;
  if (const std::optional<Box2d> projected = ProjectedBounds(obb, camera, cam_from_world)) {
    const Box2d clipped = projected->ClippedTo(camera.width, camera.height);
    if (!clipped.empty()) t.bbox_projected = clipped;
  }
  if (!t.bbox_projected && t.visible_pixels == 0) return std::nullopt;
  t.bbox_oriented_projected =
      MinimumAreaRectangle(ProjectedSilhouettePoints(obb, camera, cam_from_world));
  if (object.heading_in_box) {
    if (const std::optional<Eigen::Vector2d> heading = ImageDirectionAt(
            camera, cam_from_world, obb.center, obb.world_from_box * *object.heading_in_box)) {
      if (t.bbox_oriented) t.bbox_oriented = WithHeadingCornerFirst(*t.bbox_oriented, *heading);
      if (t.bbox_oriented_projected)
        t.bbox_oriented_projected = WithHeadingCornerFirst(*t.bbox_oriented_projected, *heading);
    }
  }
  t.in_frame = InFrameFraction(obb, camera, cam_from_world);
  int64_t unoccluded = t.visible_pixels;
  if (t.bbox_projected && count_unoccluded)
    unoccluded = std::max(unoccluded, count_unoccluded(*t.bbox_projected));
  t.visibility = unoccluded > 0 ? static_cast<double>(t.visible_pixels) / unoccluded : 0.0;
  return t;
}

}  // namespace lsds
