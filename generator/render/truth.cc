#include "generator/render/truth.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include <tbb/parallel_for.h>

#include "libs/collection/object_truth.h"
#include "libs/geometry/oriented_box.h"

namespace lsds::gen {
namespace {

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
  const Eigen::Vector3f origin = CameraCenterInWorld(frame.cam_from_world).cast<float>();
  // One pixel of margin: the centre samples of edge pixels may be jittered
  // outside the exact bounds.
  const int x0 = std::max(0, static_cast<int>(std::floor(bounds.x0)) - 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(bounds.y0)) - 1);
  const int x1 = std::min(camera.width, static_cast<int>(std::ceil(bounds.x1)) + 1);
  const int y1 = std::min(camera.height, static_cast<int>(std::ceil(bounds.y1)) + 1);
  if (x1 <= x0 || y1 <= y0) return 0;
  std::atomic<int64_t> count{0};
  tbb::parallel_for(y0, y1, [&](int y) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    int64_t row = 0;
    for (int x = x0; x < x1; ++x) {
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
                                            double extinction_per_m,
                                            uint64_t* rays) {
  const WorldState& world = scene.world();
  const PinholeCamera& camera = frame.camera;
  const auto masks =
      MeasureInstanceMasks(film.flat.at("instanceid").Get("id").uints, camera.width, camera.height);
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
    const auto mask = masks.find(p.instance_id);
    const RTCScene own = scene.ObjectScene(static_cast<int>(i));
    std::optional<ObjectTruth> t = MeasureObjectTruth(
        identity,
        camera,
        frame.cam_from_world,
        mask == masks.end() ? nullptr : &mask->second,
        [&](const Box2d& bounds) { return UnoccludedPixels(own, frame, film, bounds, rays); });
    if (!t) continue;  // nowhere near the image
    t->material = o.material;
    t->velocity = o.velocity;
    t->transmittance = std::exp(-extinction_per_m *
                                (t->obb.center - CameraCenterInWorld(frame.cam_from_world)).norm());
    truths.push_back(std::move(*t));
  }
  return truths;
}

}  // namespace lsds::gen
