#include "libs/collection/object_truth.h"

#include <algorithm>

namespace lsds {

std::unordered_map<uint32_t, InstanceMask> MeasureInstanceMasks(const std::vector<uint32_t>& ids,
                                                                int width,
                                                                int height) {
  struct Extent {
    int64_t pixels = 0;
    int x0, y0, x1, y1;
  };
  std::unordered_map<uint32_t, Extent> extents;
  uint32_t last_id = 0;
  Extent* last = nullptr;  // runs of one id are common: skip the lookup
  for (int y = 0; y < height; ++y) {
    const uint32_t* row = ids.data() + static_cast<size_t>(y) * width;
    for (int x = 0; x < width; ++x) {
      const uint32_t id = row[x];
      if (id == 0) continue;
      if (last == nullptr || id != last_id) {
        auto [it, inserted] = extents.try_emplace(id, Extent{0, x, y, x, y});
        last = &it->second, last_id = id;
      }
      ++last->pixels;
      last->x0 = std::min(last->x0, x), last->x1 = std::max(last->x1, x);
      last->y0 = std::min(last->y0, y), last->y1 = std::max(last->y1, y);
    }
  }
  std::unordered_map<uint32_t, InstanceMask> masks;
  masks.reserve(extents.size());
  for (const auto& [id, e] : extents) {
    masks[id] = {e.pixels, Box2d{double(e.x0), double(e.y0), double(e.x1 + 1), double(e.y1 + 1)}};
  }
  return masks;
}

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
