#include "generator/render/truth.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include <tbb/parallel_for.h>

#include "generator/render/embree_abi.h"
#include "generator/scene/object_library.h"  // FrontOfBuiltinClass
#include "libs/collection/object_truth.h"
#include "libs/geometry/oriented_box.h"

namespace lsds::gen {
namespace {

// Pixels whose centre sample hits the object when it is alone in the scene,
// inside `bounds`. A pixel whose centre sample already hit the object in the
// full scene (instance id layer == `visible_id`) hits it alone too: the same
// float ray meets the same triangle, occluders only remove hits. Those pixels
// are counted without a ray; `visible_id` 0 casts every ray (an id shared by
// several geometries cannot tell which one was hit).
int64_t UnoccludedPixels(RTCScene own,
                         const PlannedFrame& frame,
                         const Film& film,
                         uint32_t visible_id,
                         const Box2d& bounds,
                         uint64_t* rays) {
  const PinholeCamera& camera = frame.camera;
  const Eigen::Matrix3d world_from_cam =
      frame.cam_from_world.rotation.conjugate().toRotationMatrix();
  const Eigen::Vector3f origin = CameraCenterInWorld(frame.cam_from_world).cast<float>();
  // One pixel of margin: the centre samples of edge pixels may be jittered
  // outside the exact bounds.
  const int x0 = std::max(0, static_cast<int>(std::floor(bounds.x0)) - 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(bounds.y0)) - 1);
  const int x1 = std::min(camera.width, static_cast<int>(std::ceil(bounds.x1)) + 1);
  const int y1 = std::min(camera.height, static_cast<int>(std::ceil(bounds.y1)) + 1);
  if (x1 <= x0 || y1 <= y0) return 0;
  const std::vector<uint32_t>& ids = film.flat.at("instanceid").Get("id").uints;
  std::atomic<int64_t> count{0};
  std::atomic<uint64_t> cast{0};
  tbb::parallel_for(y0, y1, [&](int y) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    int64_t row = 0;
    uint64_t row_rays = 0;
    for (int x = x0; x < x1; ++x) {
      if (visible_id != 0 && ids[static_cast<size_t>(y) * camera.width + x] == visible_id) {
        ++row;
        continue;
      }
      ++row_rays;
      const Eigen::Vector2f s = film.centre_sample[static_cast<size_t>(y) * camera.width + x];
      const Eigen::Vector3d d = world_from_cam * camera.CamFromImage(s.cast<double>());
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
      Embree().occluded1(own, &context, &ray);
      if (ray.tfar < 0) ++row;
    }
    count += row;
    cast += row_rays;
  });
  *rays += cast;
  return count;
}

}  // namespace

std::vector<ObjectTruth> ComputeObjectTruth(const RenderScene& scene,
                                            const PlannedFrame& frame,
                                            const Film& film,
                                            double extinction_per_m,
                                            uint64_t* rays,
                                            const TruthOptions& options) {
  const WorldState& world = scene.world();
  std::map<uint32_t, int> geometries_of;  // instance id -> geometries carrying it
  for (size_t g = 0; g < scene.surface_count(); ++g) ++geometries_of[scene.surface(g).instance_id];
  const PinholeCamera& camera = frame.camera;
  const std::vector<uint32_t>& ids = film.flat.at("instanceid").Get("id").uints;
  const auto masks = MeasureInstanceMasks(ids, camera.width, camera.height);
  std::vector<ObjectTruth> truths;
  for (size_t i = 0; i < world.objects.size(); ++i) {
    const ObjectState& o = world.objects[i];
    const PlannedObject& p = *o.planned;
    if (!p.target || !o.visible || o.class_id == 0 || p.instance_id == 0) continue;
    ObjectIdentity identity;
    identity.instance_id = p.instance_id;
    identity.class_id = o.class_id;
    identity.name = p.name;
    identity.asset = o.asset;
    identity.obb = o.Box();
    identity.heading_in_box = FrontOfBuiltinClass(o.asset);
    const auto mask = masks.find(p.instance_id);
    const RTCScene own = scene.ObjectScene(static_cast<int>(i));
    const uint32_t visible_id =
        options.reuse_visible_pixels && geometries_of[p.instance_id] == 1 ? p.instance_id : 0;
    std::optional<ObjectTruth> t =
        MeasureObjectTruth(identity,
                           camera,
                           frame.cam_from_world,
                           {ids.data(), camera.width, camera.height},
                           mask == masks.end() ? nullptr : &mask->second,
                           [&](const Box2d& bounds) {
                             return UnoccludedPixels(own, frame, film, visible_id, bounds, rays);
                           });
    if (!t) continue;  // nowhere near the image
    t->material = o.material;
    t->velocity = o.velocity;
    t->transmittance = std::exp(
        -extinction_per_m * (o.Box().center - CameraCenterInWorld(frame.cam_from_world)).norm());
    truths.push_back(std::move(*t));
  }
  return truths;
}

}  // namespace lsds::gen
