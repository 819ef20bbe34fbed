#include "generator/render/truth.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include <tbb/parallel_for.h>

#include "libs/geometry/oriented_box.h"

namespace lsds::gen {
namespace {

struct MaskStats {
  int64_t pixels = 0;
  int x0 = std::numeric_limits<int>::max(),
      y0 = std::numeric_limits<int>::max(), x1 = -1, y1 = -1;
};

// Pixels whose centre sample hits the object when it is alone in the scene,
// inside `bounds`.
int64_t UnoccludedPixels(RTCScene own,
                         const PlannedFrame& frame,
                         const Film& film,
                         const Box2d& bounds,
                         uint64_t* rays) {
  const PinholeCamera& camera = frame.camera;
  const Eigen::Matrix3d world_from_cam =
      frame.cam_from_world.rotation.conjugate().toRotationMatrix();
  const Eigen::Vector3f origin =
      CameraCenterInWorld(frame.cam_from_world).cast<float>();
  // One pixel of margin: the centre samples of edge pixels may be jittered
  // outside the exact bounds.
  const int x0 = std::max(0, static_cast<int>(std::floor(bounds.x0)) - 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(bounds.y0)) - 1);
  const int x1 =
      std::min(camera.width, static_cast<int>(std::ceil(bounds.x1)) + 1);
  const int y1 =
      std::min(camera.height, static_cast<int>(std::ceil(bounds.y1)) + 1);
  if (x1 <= x0 || y1 <= y0) return 0;
  std::atomic<int64_t> count{0};
  tbb::parallel_for(y0, y1, [&](int y) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    int64_t row = 0;
    for (int x = x0; x < x1; ++x) {
      const Eigen::Vector2f s =
          film.centre_sample[static_cast<size_t>(y) * camera.width + x];
      const Eigen::Vector3d d =
          world_from_cam * camera.CamFromImage(s.cast<double>());
      RTCRay ray;
      ray.org_x = origin.x();
      ray.org_y = origin.y();
      ray.org_z = origin.z();
      ray.dir_x = static_cast<float>(d.x());
      ray.dir_y = static_cast<float>(d.y());
      ray.dir_z = static_cast<float>(d.z());
      ray.tnear = 0.f;
      ray.tfar = std::numeric_limits<float>::infinity();
      ray.mask = 0xffffffffu;
      ray.flags = 0;
      ray.time = 0.f;
      rtcOccluded1(own, &context, &ray);
      if (ray.tfar < 0) ++row;
    }
    count += row;
  });
  *rays += static_cast<uint64_t>(x1 - x0) * (y1 - y0);
  return count;
}

}  // namespace

std::vector<ObjectTruth> ComputeObjectTruth(const RenderScene& scene,
                                            const PlannedFrame& frame,
                                            const Film& film,
                                            uint64_t* rays) {
  const WorldState& world = scene.world();
  const PinholeCamera& camera = frame.camera;
  // One pass over the instance layer for every object's mask statistics.
  std::map<uint32_t, MaskStats> stats;
  const std::vector<uint32_t>& ids = film.flat.at("instanceid").Get("id").uints;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const uint32_t id = ids[static_cast<size_t>(y) * camera.width + x];
      if (id == 0) continue;
      MaskStats& s = stats[id];
      ++s.pixels;
      s.x0 = std::min(s.x0, x);
      s.y0 = std::min(s.y0, y);
      s.x1 = std::max(s.x1, x + 1);
      s.y1 = std::max(s.y1, y + 1);
    }
  }
  std::vector<ObjectTruth> truths;
  for (size_t i = 0; i < world.objects.size(); ++i) {
    const ObjectState& o = world.objects[i];
    const PlannedObject& p = *o.planned;
    if (!p.target || !o.visible || p.class_id == 0 || p.instance_id == 0)
      continue;
    ObjectTruth t;
    t.instance_id = p.instance_id;
    t.class_id = p.class_id;
    t.name = p.name;
    t.obb = o.Box();
    const auto it = stats.find(p.instance_id);
    if (it != stats.end()) {
      t.visible_pixels = it->second.pixels;
      t.bbox = Box2d{static_cast<double>(it->second.x0),
                     static_cast<double>(it->second.y0),
                     static_cast<double>(it->second.x1),
                     static_cast<double>(it->second.y1)};
    }
    const std::optional<Box2d> projected =
        ProjectedBounds(t.obb, camera, frame.cam_from_world);
    t.in_frame = InFrameFraction(t.obb, camera, frame.cam_from_world);
    if (projected) {
      const Box2d clipped = projected->ClippedTo(camera.width, camera.height);
      if (!clipped.empty()) t.bbox_projected = clipped;
    }
    if (!t.bbox_projected && t.visible_pixels == 0)
      continue;  // nowhere near the image
    if (t.bbox_projected) {
      const int64_t unoccluded =
          UnoccludedPixels(scene.ObjectScene(static_cast<int>(i)),
                           frame,
                           film,
                           *t.bbox_projected,
                           rays);
      const int64_t denominator = std::max(unoccluded, t.visible_pixels);
      t.visibility = denominator > 0
                         ? static_cast<double>(t.visible_pixels) / denominator
                         : 0.0;
    }
    truths.push_back(t);
  }
  return truths;
}

}  // namespace lsds::gen
