// Benchmark of `lsds generate`: renders the demo scene at several sizes and
// prints Mrays/s, s/frame, and the floor for the same frames = the Embree ray
// casts alone (the same primary and shadow rays, no shading, no films) + the
// encoding of the same EXR files alone, with the ratio frame time / floor.
//
//   bench_generate [--frames N] [--sizes 512,1024] [--spp S] [--threads T]
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/render/embree_scene.h"
#include "generator/render/integrator.h"
#include "generator/render/sky.h"
#include "libs/collection/collection_builder.h"
#include "libs/util/strings.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace lsds;
using namespace lsds::gen;

namespace {

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The floor's ray casts: per pixel the same spp camera rays and, for hits
// facing the sun, one shadow ray.
uint64_t CastRaysOnly(const RenderScene& scene,
                      const Sky& sky,
                      const PlannedFrame& frame,
                      const SamplerSettings& sampler) {
  const PinholeCamera& camera = frame.camera;
  const Eigen::Matrix3d world_from_cam =
      frame.cam_from_world.rotation.conjugate().toRotationMatrix();
  const Eigen::Vector3f origin = CameraCenterInWorld(frame.cam_from_world).cast<float>();
  const Eigen::Vector3f to_sun = sky.to_sun().cast<float>();
  std::atomic<uint64_t> total{0};
  tbb::parallel_for(
      tbb::blocked_range2d<int>(0, camera.height, 16, 0, camera.width, 16),
      [&](const tbb::blocked_range2d<int>& r) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        std::vector<Eigen::Vector2d> samples(sampler.spp);
        uint64_t rays = 0;
        for (int y = r.rows().begin(); y < r.rows().end(); ++y) {
          for (int x = r.cols().begin(); x < r.cols().end(); ++x) {
            PixelSamples(sampler, frame.index, x, y, samples.data());
            for (const Eigen::Vector2d& s : samples) {
              const Eigen::Vector3f d = (world_from_cam * camera.CamFromImage(s)).cast<float>();
              RTCRayHit rh;
              rh.ray.org_x = origin.x(), rh.ray.org_y = origin.y(), rh.ray.org_z = origin.z();
              rh.ray.dir_x = d.x(), rh.ray.dir_y = d.y(), rh.ray.dir_z = d.z();
              rh.ray.tnear = 0, rh.ray.tfar = std::numeric_limits<float>::infinity();
              rh.ray.mask = ~0u, rh.ray.flags = 0, rh.ray.time = 0;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rtcIntersect1(scene.scene(), &context, &rh);
              ++rays;
              if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
              Eigen::Vector3f n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
              n.normalize();
              if (n.dot(d) > 0) n = -n;
              if (n.dot(to_sun) <= 0) continue;
              const Eigen::Vector3f p = origin + rh.ray.tfar * d + 1e-3f * n;
              RTCRay ray;
              ray.org_x = p.x(), ray.org_y = p.y(), ray.org_z = p.z();
              ray.dir_x = to_sun.x(), ray.dir_y = to_sun.y(), ray.dir_z = to_sun.z();
              ray.tnear = 0, ray.tfar = std::numeric_limits<float>::infinity();
              ray.mask = ~0u, ray.flags = 0, ray.time = 0;
              rtcOccluded1(scene.scene(), &context, &ray);
              ++rays;
            }
          }
        }
        total += rays;
      });
  return total;
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 4, spp = 4, threads = 0;
  std::vector<int> sizes = {512, 1024};
  std::vector<std::string> post_process;  // LCAP PPMaterial effects, to measure their cost
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--frames")
      frames = std::atoi(argv[i + 1]);
    else if (flag == "--spp")
      spp = std::atoi(argv[i + 1]);
    else if (flag == "--threads")
      threads = std::atoi(argv[i + 1]);
    else if (flag == "--post-process")
      post_process = Split(argv[i + 1], ',');
    else if (flag == "--sizes") {
      sizes.clear();
      for (const std::string& s : Split(argv[i + 1], ',')) sizes.push_back(std::atoi(s.c_str()));
    } else {
      std::fprintf(stderr,
                   "usage: bench_generate [--frames N] [--sizes 512,1024] "
                   "[--spp S] [--threads T] [--post-process EdgeBlur,...]\n");
      return 2;
    }
  }
  std::optional<tbb::global_control> control;
  if (threads > 0) control.emplace(tbb::global_control::max_allowed_parallelism, threads);
  const fs::path root = fs::temp_directory_path() / "lsds_bench_generate";
  std::printf("lsds generate benchmark: demo scene, %d frames, spp %d, post-process [%s]\n",
              frames,
              spp,
              Join(post_process, ",").c_str());
  std::printf("%6s %9s %9s %10s %10s %10s %7s\n",
              "size",
              "s/frame",
              "Mrays/s",
              "rays s/f",
              "encode s/f",
              "floor s/f",
              "ratio");
  for (int size : sizes) {
    DemoOptions demo;
    demo.frames = frames;
    demo.width = demo.height = size;
    Plan plan = MakeDemoPlan(demo);
    plan.post_process = post_process;
    GenerateOptions options;
    options.output = root / "full";
    options.force = true;
    options.progress = false;
    options.spp = spp;
    const GenerateSummary summary = GenerateCollection(plan, options);
    const double per_frame = summary.total_seconds / frames;

    // The floor: ray casts alone, then the encoding of the same films alone.
    EmbreeDevice device;
    const SceneAssets assets = BuildSceneAssets(plan);
    const Sky sky(plan);
    const SamplerSettings sampler{spp, 1.0, plan.seed};
    double ray_seconds = 0, encode_seconds = 0;
    uint64_t floor_rays = 0;
    const CollectionHeader header = MakeHeader(plan, options);
    const fs::path encode_root = root / "encode";
    fs::remove_all(encode_root);
    for (const LayerInfo& layer : header.layers) fs::create_directories(encode_root / layer.name);
    for (const PlannedFrame& frame : plan.frames) {
      const RenderScene scene(device, plan, assets, WorldAt(plan, frame));
      Clock::time_point t = Clock::now();
      floor_rays += CastRaysOnly(scene, sky, frame, sampler);
      ray_seconds += Since(t);
      RenderSettings settings;
      settings.sampler = sampler;
      const Film film = RenderFrame(scene, sky, frame, {}, settings);
      t = Clock::now();
      CameraTruth camera;
      camera.intrinsics = frame.camera;
      camera.cam_from_world_rotation = frame.cam_from_world.rotation.toRotationMatrix();
      camera.cam_from_world_translation = frame.cam_from_world.translation;
      WriteFrameLayers(encode_root, header, frame.index, camera, {&film.flat, &film.bundle});
      encode_seconds += Since(t);
    }
    const double floor = (ray_seconds + encode_seconds) / frames;
    std::printf("%6d %9.3f %9.2f %10.3f %10.3f %10.3f %7.2f\n",
                size,
                per_frame,
                summary.rays / summary.total_seconds / 1e6,
                ray_seconds / frames,
                encode_seconds / frames,
                floor,
                per_frame / floor);
    std::printf(
        "       (generate: render %.3f s/frame, write %.3f s/frame; floor rays "
        "%.2f Mrays/s)\n",
        summary.render_seconds / frames,
        summary.write_seconds / frames,
        floor_rays / ray_seconds / 1e6);
  }
  fs::remove_all(root);
  return 0;
}
