#include "generator/estimate.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "generator/render/embree_abi.h"
#include "generator/render/embree_scene.h"
#include "generator/scene/world.h"
#include "libs/geometry/oriented_box.h"

namespace lsds::gen {
namespace {

std::mutex stats_mutex;
EstimateStats stats;

RTCRay Ray(const Eigen::Vector3f& origin, const Eigen::Vector3d& d) {
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
  ray.id = 0;
  return ray;
}

class Estimator {
 public:
  FrameMeasure operator()(const Plan& plan, const PlannedFrame& frame) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!device_) device_ = std::make_unique<EmbreeDevice>();
    // Class swaps of this frame need their shapes: the assets are built with
    // the frame, and kept per set of swaps (a class quota's redraws come back
    // to the same few sets).
    std::string swaps;
    for (const ObjectChange& c : frame.changes)
      if (c.asset) swaps += c.object + "=" + *c.asset + ";";
    if (!assets_ || swaps != assets_key_) {
      auto& cached = assets_cache_[swaps];
      if (!cached) {
        if (assets_cache_.size() > kMaxCachedAssets) {
          assets_cache_.clear();  // bounded memory; rebuilt on demand
          assets_ = nullptr;
        }
        Plan with_frame = plan;
        with_frame.frames = {frame};
        auto& slot = assets_cache_[swaps];
        slot = std::make_shared<SceneAssets>(BuildSceneAssets(with_frame));
        assets_ = slot;
      } else {
        assets_ = cached;
      }
      assets_key_ = swaps;
    }
    WorldState world = WorldAt(plan, frame);
    if (!scene_) {
      scene_ = std::make_unique<RenderScene>(*device_, plan, *assets_, world);
      world_ = std::move(world);
    } else if (!(world_ == world)) {
      // In place: the objects that did not change keep their BVHs (the
      // scene holds its own meshes, so it outlives a change of assets).
      scene_->Update(*device_, *assets_, world);
      world_ = std::move(world);
    }
    FrameMeasure measure;
    int64_t rays = 0;
    for (size_t i = 0; i < world_.objects.size(); ++i) {
      const ObjectState& o = world_.objects[i];
      const PlannedObject& p = *o.planned;
      if (!p.target || !o.visible || o.class_id == 0 || p.instance_id == 0) continue;
      const OrientedBox box = o.Box();
      const auto bounds = ProjectedBounds(box, frame.camera, frame.cam_from_world);
      if (!bounds) continue;
      TargetMeasure t;
      t.object = p.name;
      t.values = GeometricMeasures(box, frame.camera, frame.cam_from_world);
      t.values["class"] = o.class_id;
      if (t.values["in_frame"] <= 0) continue;  // nowhere near the image
      const double visibility = Visibility(static_cast<int>(i), frame, *bounds, &rays);
      t.values["visibility"] = visibility;
      t.values["occlusion"] = 1.0 - visibility;
      measure.targets.push_back(std::move(t));
    }
    std::lock_guard<std::mutex> lock(stats_mutex);
    ++stats.frames;
    stats.rays += rays;
    stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return measure;
  }

 private:
  // Hits on object i in the full scene over hits in its own scene, on a grid
  // of pixel centres over its projected box clipped to the image.
  double Visibility(int i, const PlannedFrame& frame, const Box2d& b, int64_t* rays) const {
    const PinholeCamera& camera = frame.camera;
    const double x0 = std::max(0.0, b.x0), y0 = std::max(0.0, b.y0);
    const double x1 = std::min<double>(camera.width, b.x1);
    const double y1 = std::min<double>(camera.height, b.y1);
    if (x1 <= x0 || y1 <= y0) return 0;
    const int ix0 = static_cast<int>(std::floor(x0)), iy0 = static_cast<int>(std::floor(y0));
    const int ix1 = static_cast<int>(std::ceil(x1)), iy1 = static_cast<int>(std::ceil(y1));
    const int stride = std::max(
        1, (std::max(ix1 - ix0, iy1 - iy0) + kEstimateRaysPerSide - 1) / kEstimateRaysPerSide);
    const Eigen::Matrix3d world_from_cam =
        frame.cam_from_world.rotation.conjugate().toRotationMatrix();
    const Eigen::Vector3f origin = CameraCenterInWorld(frame.cam_from_world).cast<float>();
    const RTCScene own = scene_->ObjectScene(i);
    if (!own) return 0;
    int64_t visible = 0, covered = 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int y = iy0 + stride / 2; y < iy1; y += stride)
      for (int x = ix0 + stride / 2; x < ix1; x += stride) {
        const Eigen::Vector3d d =
            world_from_cam * camera.CamFromImage(Eigen::Vector2d(x + 0.5, y + 0.5));
        RTCRay alone = Ray(origin, d);
        Embree().occluded1(own, &context, &alone);
        RTCRayHit hit;
        hit.ray = Ray(origin, d);
        hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        Embree().intersect1(scene_->scene(), &context, &hit);
        *rays += 2;
        if (alone.tfar < 0) ++covered;
        if (hit.hit.geomID != RTC_INVALID_GEOMETRY_ID &&
            scene_->surface(hit.hit.geomID).object == i)
          ++visible;
      }
    const int64_t denominator = std::max(covered, visible);
    return denominator == 0 ? 0.0 : static_cast<double>(visible) / denominator;
  }

  static constexpr size_t kMaxCachedAssets = 32;
  std::unique_ptr<EmbreeDevice> device_;
  std::map<std::string, std::shared_ptr<SceneAssets>> assets_cache_;
  std::shared_ptr<SceneAssets> assets_;
  std::string assets_key_;
  std::unique_ptr<RenderScene> scene_;
  WorldState world_;
};

}  // namespace

FrameEstimatorFactory MakeFrameEstimatorFactory() {
  return [] {
    auto estimator = std::make_shared<Estimator>();
    return FrameEstimator([estimator](const Plan& plan, const PlannedFrame& frame) {
      return (*estimator)(plan, frame);
    });
  };
}

EstimateStats GetEstimateStats() {
  std::lock_guard<std::mutex> lock(stats_mutex);
  return stats;
}

}  // namespace lsds::gen
