// Benchmark of `lsds generate` (issues 3 and 20): renders the demo scene at
// several sizes in several storage layouts (BUNDLE/WORLDPOSITION[/MOTION],
// motion float when left out: full/float as in format 1.0, compact/float,
// compact/residual, residual/residual/residual, the generator's default),
// and prints s/frame, Mrays/s, bytes per frame per layer and in total, the
// floor for the same frames = the Embree ray casts alone (the same primary and
// shadow rays, no shading, no films) + the encoding of the same EXR files alone,
// with the ratio frame time / floor (over the whole collection, and per frame
// once the render-while-write pipeline is full), and, when `blender` is
// installed, the same frames rendered by Blender Cycles
// (bench/peers/cycles_demo.py) with the ratio. Each figure is the median of
// --repeats runs (3), lsds, its floor and Cycles taking turns.
//
//   bench_generate [--frames N] [--sizes 512,1024] [--spp S] [--threads T] [--repeats R]
//                  [--layouts full/float,compact/float,compact/residual,residual/residual/residual]
//                  [--blender PATH|none]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/render/embree_scene.h"
#include "generator/render/exposure.h"
#include "generator/render/integrator.h"
#include "generator/render/ray_casts.h"
#include "generator/render/sky.h"
#include "generator/scene/materials.h"
#include "libs/collection/collection_builder.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/process.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"
#include "tests/build_paths.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace lsds;
using namespace lsds::gen;

namespace {

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Bytes of every file under `root`/`folder`.
uintmax_t FolderBytes(const fs::path& folder) {
  uintmax_t bytes = 0;
  std::error_code ec;
  for (const auto& entry : fs::recursive_directory_iterator(folder, ec)) {
    if (entry.is_regular_file()) bytes += entry.file_size();
  }
  return bytes;
}

double Mb(double bytes) { return bytes / 1e6; }

// User + system CPU seconds of this process (RUSAGE_SELF) or of its waited-for
// children (RUSAGE_CHILDREN): beside wall time, the work on a loaded machine.
double CpuSeconds(int who) {
  rusage usage{};
  getrusage(who, &usage);
  auto seconds = [](const timeval& t) { return t.tv_sec + 1e-6 * t.tv_usec; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

struct PeerRun {
  bool ran = false;
  double seconds = 0;      // the whole process
  double cpu_seconds = 0;  // its user + system time
  uintmax_t bytes = 0;
};

// Blender Cycles rendering the same-size scene with depth, normal, position,
// object index and vector passes (bench/peers/cycles_demo.py).
PeerRun RunCycles(
    const std::string& blender, int size, int frames, int spp, int threads, const fs::path& out) {
  PeerRun run;
  fs::remove_all(out);
  fs::create_directories(out);
  const std::string command =
      blender + " -b --factory-startup -noaudio --python " + ::lsds::testing::SourceDir() +
      "/bench/peers/cycles_demo.py -- " + std::to_string(size) + " " + std::to_string(size) + " " +
      std::to_string(frames) + " " + std::to_string(spp) + " " + out.string() + " " +
      std::to_string(threads) + " > " + (out / "blender.log").string() + " 2>&1";
  const Clock::time_point t = Clock::now();
  const double cpu = CpuSeconds(RUSAGE_CHILDREN);
  const int status = std::system(command.c_str());
  run.seconds = Since(t);
  run.cpu_seconds = CpuSeconds(RUSAGE_CHILDREN) - cpu;
  run.ran = status == 0;
  if (!run.ran) std::printf("       (blender failed: see %s)\n", (out / "blender.log").c_str());
  fs::remove(out / "blender.log");
  run.bytes = FolderBytes(out);
  return run;
}

// The floor's ray casts: per pixel the same spp camera rays, for hits facing
// the sun one shadow ray, and, when there is a previous frame, the centre
// sample's disocclusion ray into the previous scene (motion truth), cast as
// the renderer casts them (a 2x2 block of pixels' rays of each kind in
// packets, in a coherent context: ray_casts.h). The disocclusion ray goes to
// the point seen now (the renderer maps a moved object's point back to where
// it was first: the same count of rays).
uint64_t CastRaysOnly(const RenderScene& scene,
                      const Sky& sky,
                      const PlannedFrame& frame,
                      const SamplerSettings& sampler,
                      const PlannedFrame* previous_frame,
                      const RenderScene* previous_scene) {
  const PinholeCamera& camera = frame.camera;
  const Eigen::Matrix3d world_from_cam =
      frame.cam_from_world.rotation.conjugate().toRotationMatrix();
  const Eigen::Vector3d origin = CameraCenterInWorld(frame.cam_from_world);
  const int spp = sampler.spp;
  const FrameSampler frame_sampler(sampler, frame.index);
  std::atomic<uint64_t> total{0};
  tbb::parallel_for(
      tbb::blocked_range2d<int>(0,
                                (camera.height + kBlock - 1) / kBlock,
                                16 / kBlock,
                                0,
                                (camera.width + kBlock - 1) / kBlock,
                                16 / kBlock),
      [&](const tbb::blocked_range2d<int>& r) {
        RTCIntersectContext context;
        InitCoherentContext(&context);
        const int block_rays = kBlock * kBlock * spp;
        std::vector<Eigen::Vector2d> samples(block_rays);
        std::vector<Eigen::Vector3d> directions(block_rays), shadow_origins(block_rays);
        std::vector<EmbreeHit> hits(block_rays);
        std::vector<uint8_t> facing_sun(block_rays), occluded(block_rays);
        Eigen::Vector3d to_before[kBlock * kBlock];
        float length_to_before[kBlock * kBlock];
        uint8_t test_before[kBlock * kBlock], hidden_before[kBlock * kBlock];
        const Eigen::Vector3d previous_centre =
            previous_frame != nullptr ? CameraCenterInWorld(previous_frame->cam_from_world)
                                      : Eigen::Vector3d::Zero();
        uint64_t rays = 0;
        for (int row = r.rows().begin(); row < r.rows().end(); ++row) {
          for (int col = r.cols().begin(); col < r.cols().end(); ++col) {
            int x[kBlock * kBlock], y[kBlock * kBlock];
            const int pixels = BlockPixels(row, col, camera.width, camera.height, x, y);
            const int count = pixels * spp;
            for (int p = 0; p < pixels; ++p)
              frame_sampler.PixelSamples(x[p], y[p], &samples[p * spp]);
            for (int i = 0; i < count; ++i)
              directions[i] = world_from_cam * camera.CamFromImage(samples[i]);
            TraceRays(scene.scene(), origin, directions.data(), count, &context, hits.data());
            rays += count;
            for (int i = 0; i < count; ++i) {
              facing_sun[i] = 0;
              if (hits[i].geom == RTC_INVALID_GEOMETRY_ID) continue;
              // The triangle's normal, without the renderer's exact hit.
              const Surface& s = scene.surface(hits[i].geom);
              const Eigen::Vector3i& tri = s.triangles[hits[i].prim];
              Eigen::Vector3d n = (s.positions[tri[1]] - s.positions[tri[0]])
                                      .cross(s.positions[tri[2]] - s.positions[tri[0]])
                                      .cast<double>()
                                      .normalized();
              if (n.dot(directions[i]) > 0) n = -n;
              if (n.dot(sky.to_sun()) <= 0) continue;
              facing_sun[i] = 1;
              shadow_origins[i] = origin + hits[i].tfar * directions[i] + 1e-3 * n;
              ++rays;
            }
            OccludedRays(scene.scene(),
                         shadow_origins.data(),
                         sky.to_sun(),
                         facing_sun.data(),
                         count,
                         &context,
                         occluded.data());
            if (previous_scene == nullptr) continue;
            for (int p = 0; p < pixels; ++p) {
              const EmbreeHit& centre = hits[p * spp];
              test_before[p] = centre.geom != RTC_INVALID_GEOMETRY_ID &&
                               DisocclusionRay(previous_centre,
                                               origin + centre.tfar * directions[p * spp],
                                               &to_before[p],
                                               &length_to_before[p]);
              rays += test_before[p];
            }
            OccludedSegments(previous_scene->scene(),
                             previous_centre,
                             to_before,
                             length_to_before,
                             test_before,
                             pixels,
                             &context,
                             hidden_before);
          }
        }
        total += rays;
      });
  return total;
}

// A storage layout under test: BUNDLE[/WORLDPOSITION[/MOTION]], motion float
// when left out (e.g. compact/residual), with the generator's options for it.
struct Layout {
  std::string name;
  GenerateOptions options;
  CollectionHeader header;
};

bool ParseLayout(
    const std::string& name, const Plan& plan, int spp, const fs::path& root, Layout* layout) {
  layout->name = name;
  GenerateOptions& options = layout->options;
  options.output = root / ("generate_" + name);
  options.force = true;
  options.progress = false;
  options.spp = spp;
  const std::vector<std::string> parts = Split(name, '/');
  options.layouts.motion = FlatLayout::kFloat;
  if (!ParseBundleLayout(parts[0], &options.layouts.bundle) ||
      (parts.size() > 1 && !ParseFlatLayout(parts[1], &options.layouts.worldposition)) ||
      (parts.size() > 2 && !ParseFlatLayout(parts[2], &options.layouts.motion)) ||
      parts.size() > 3) {
    return false;
  }
  layout->header = MakeHeader(plan, options);
  return true;
}

// What one repeat measures: each layout's generate run, the floor (the same
// rays alone, then each layout's encoding of the same films alone) and
// Blender Cycles.
struct Repeat {
  std::vector<GenerateSummary> generate;     // per layout
  std::vector<double> generate_cpu_seconds;  // per layout
  double ray_seconds = 0;
  uint64_t floor_rays = 0;
  std::vector<double> encode_seconds;  // per layout
  std::optional<double> cycles_seconds;
  double cycles_cpu_seconds = 0;
};

// The floor for `plan`'s frames: ray casts alone, then the encoding of the
// same films alone in each layout.
void MeasureFloor(const Plan& plan,
                  int spp,
                  const std::vector<Layout>& layouts,
                  const fs::path& root,
                  Repeat* repeat) {
  EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);
  const Sky sky(plan);
  const SamplerSettings sampler{spp, 1.0, plan.seed};
  const fs::path encode_root = root / "encode";
  repeat->encode_seconds.assign(layouts.size(), 0.0);
  // The films the generator encodes: motion against the previous frame (the
  // demo is one shot), so that the floor encodes the same content.
  std::unique_ptr<RenderScene> previous_scene;
  std::optional<WorldState> previous_world;
  const PlannedFrame* previous_frame = nullptr;
  for (const PlannedFrame& frame : plan.frames) {
    WorldState world = WorldAt(plan, frame);
    auto scene = std::make_unique<RenderScene>(device, plan, assets, world);
    Clock::time_point t = Clock::now();
    repeat->floor_rays +=
        CastRaysOnly(*scene, sky, frame, sampler, previous_frame, previous_scene.get());
    repeat->ray_seconds += Since(t);
    RenderSettings settings;
    settings.sampler = sampler;
    PreviousView previous;
    FrameImages::MotionReference motion;
    if (previous_frame != nullptr) {
      previous = {previous_frame, &*previous_world, previous_scene.get()};
      CameraTruth& before = motion.previous_camera.emplace();
      before.intrinsics = previous_frame->camera;
      SetCamFromWorld(previous_frame->cam_from_world, &before);
    }
    const Film film = RenderFrame(*scene, sky, frame, previous, settings);
    CameraTruth camera;  // as the generator records it
    camera.intrinsics = frame.camera;
    SetCamFromWorld(frame.cam_from_world, &camera);
    for (size_t i = 0; i < layouts.size(); ++i) {
      fs::remove_all(encode_root);
      for (const LayerInfo& layer : layouts[i].header.layers)
        fs::create_directories(encode_root / layer.name);
      t = Clock::now();
      WriteFrameLayers(
          encode_root,
          layouts[i].header,
          frame.index,
          camera,
          {&film.flat, &film.bundle, BundleSampling{sampler, frame.index, std::nullopt}, motion});
      repeat->encode_seconds[i] += Since(t);
    }
    previous_scene = std::move(scene);
    previous_world = std::move(world);
    previous_frame = &frame;
  }
  fs::remove_all(encode_root);
}

// The median of what `value` gives for each repeat.
template <typename Fn>
double MedianOver(const std::vector<Repeat>& repeats, Fn value) {
  std::vector<double> values;
  for (const Repeat& r : repeats) values.push_back(value(r));
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The cost of the light, camera and material features, each as the
// ratio of the frame time with it to the frame time without it: auto exposure
// (metering + scaling the rgb, after RenderFrame), the procedural material
// variation (patterns and patches over a plain mottled albedo, measured per
// albedo evaluation times the frame's spp * pixels shading points), and the
// filmic tone curve of the 8-bit export against the plain encoding (clamp).
// The photometric units cost nothing at render time (constants per frame).
void PrintFeatureCosts(const Plan& plan, int spp) {
  EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);
  const Sky sky(plan);
  RenderSettings settings;
  settings.sampler = {spp, 1.0, plan.seed};
  double render_s = 0, per_sample_s = 0, shaded_s = 0, exposure_s = 0, clamp_s = 0, filmic_s = 0;
  size_t shading_points = 0;
  // Reused films, as the generator reuses them: the timings leave out the
  // page faults of fresh ones.
  Film film, per_sample_film;
  for (const PlannedFrame& frame : plan.frames) {
    const RenderScene scene(device, plan, assets, WorldAt(plan, frame));
    if (&frame == &plan.frames.front()) {
      RenderFrame(scene, sky, frame, {}, settings, &film);
      RenderFrame(scene, sky, frame, {}, settings, &per_sample_film);
    }
    Clock::time_point t = Clock::now();
    RenderFrame(scene, sky, frame, {}, settings, &film);
    render_s += Since(t);
    // The same frame with the albedo and cloud shadow at every sample.
    RenderSettings per_sample = settings;
    per_sample.reuse_smooth_fields = false;
    t = Clock::now();
    RenderFrame(scene, sky, frame, {}, per_sample, &per_sample_film);
    per_sample_s += Since(t);
    // The same frame with every sample shaded, not diffuse pixels once.
    RenderSettings every_sample = settings;
    every_sample.shade_pixels_once = false;
    t = Clock::now();
    RenderFrame(scene, sky, frame, {}, every_sample, &per_sample_film);
    shaded_s += Since(t);
    shading_points += static_cast<size_t>(frame.camera.width) * frame.camera.height * spp;
    t = Clock::now();
    const FrameExposure e = MeterExposure(PlannedExposure(), film);
    ApplyExposure(e, &film);
    exposure_s += Since(t);
    imaging::DisplayOptions display;
    display.tonemap = imaging::ToneMap::kClamp;
    // The sRGB table is built on first use: not part of either timing.
    if (&frame == &plan.frames.front()) imaging::ToSrgb8(film.flat.at("rgb"), display);
    t = Clock::now();
    const cv::Mat plain = imaging::ToSrgb8(film.flat.at("rgb"), display);
    clamp_s += Since(t);
    display.tonemap = imaging::ToneMap::kFilmic;
    t = Clock::now();
    const cv::Mat filmic = imaging::ToSrgb8(film.flat.at("rgb"), display);
    filmic_s += Since(t);
  }
  // Albedo evaluations: the families' patterns against plain mottling.
  const Perlin noise(3);
  // The fastest of 7 runs of each: the machine's load only ever adds time.
  const int kCalls = 200000;
  auto time_albedo = [&](const Material& m) {
    double best = 1e30;
    float sink = 0;
    for (int run = 0; run < 7; ++run) {
      const Clock::time_point t = Clock::now();
      for (int i = 0; i < kCalls; ++i)
        sink += Albedo(m, noise, Eigen::Vector3f(i * 0.37f, i * 0.11f, 0.5f)).x();
      best = std::min(best, Since(t) / kCalls);
    }
    if (sink < 0) std::printf(" ");  // keeps the loop
    return best;
  };
  std::printf("\nfeature costs (issue 16), %zu frames: frame render %.3f s/frame\n",
              plan.frames.size(),
              render_s / plan.frames.size());
  std::printf("  %-34s %10s %8s\n", "feature", "s/frame", "ratio");
  const double frame_s = render_s / plan.frames.size();
  std::printf("  %-34s %10.4f %8.3f\n",
              "auto exposure (meter + scale)",
              exposure_s / plan.frames.size(),
              (frame_s + exposure_s / plan.frames.size()) / frame_s);
  std::printf("  %-34s %10.4f %8.3f\n",
              "smooth fields per sample, not pixel",
              (per_sample_s - render_s) / plan.frames.size(),
              per_sample_s / render_s);
  std::printf("  %-34s %10.4f %8.3f\n",
              "every sample shaded, not once",
              (shaded_s - render_s) / plan.frames.size(),
              shaded_s / render_s);
  for (const char* name : {"grassy", "sandy", "rocky", "asphalt", "metal", "painted_red"}) {
    const Material& m = FindMaterial(name, "bench");
    Material plain = m;
    plain.pattern = Pattern::kMottled;
    plain.patches = 0;
    const double extra =
        (time_albedo(m) - time_albedo(plain)) * shading_points / plan.frames.size();
    std::printf("  %-34s %10.4f %8.3f\n",
                ("material variation: " + std::string(name)).c_str(),
                extra,
                (frame_s + extra) / frame_s);
  }
  std::printf("  %-34s %10.4f %8.3f  (of the clamp encoding, %.4f s/frame)\n",
              "filmic tone curve (8-bit export)",
              filmic_s / plan.frames.size(),
              filmic_s / clamp_s,
              clamp_s / plan.frames.size());
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 4, spp = 4, threads = 0, repeats = 3;
  std::vector<int> sizes = {512, 1024};
  std::vector<std::string> post_process;  // LCAP PPMaterial effects, to measure their cost
  std::vector<std::string> layouts = {
      "full/float", "compact/float", "compact/residual", "residual/residual/residual"};
  std::string blender = FindOnPath("blender");
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--frames")
      frames = std::atoi(argv[i + 1]);
    else if (flag == "--spp")
      spp = std::atoi(argv[i + 1]);
    else if (flag == "--threads")
      threads = std::atoi(argv[i + 1]);
    else if (flag == "--repeats")
      repeats = std::max(1, std::atoi(argv[i + 1]));
    else if (flag == "--post-process")
      post_process = Split(argv[i + 1], ',');
    else if (flag == "--sizes") {
      sizes.clear();
      for (const std::string& s : Split(argv[i + 1], ',')) sizes.push_back(std::atoi(s.c_str()));
    } else if (flag == "--layouts") {
      layouts = Split(argv[i + 1], ',');
    } else if (flag == "--blender") {
      blender = std::string(argv[i + 1]) == "none" ? "" : argv[i + 1];
    } else {
      std::fprintf(stderr,
                   "usage: bench_generate [--frames N] [--sizes 512,1024] "
                   "[--spp S] [--threads T] [--repeats R] "
                   "[--layouts full/float,compact/residual,...] "
                   "[--blender PATH|none] "
                   "[--post-process EdgeBlur,...]\n");
      return 2;
    }
  }
  const ThreadLimit control(threads);
  const fs::path root = fs::temp_directory_path() / "lsds_bench_generate";
  std::printf(
      "lsds generate benchmark: demo scene, %d frames, spp %d, threads %s, post-process [%s]\n",
      frames,
      spp,
      threads > 0 ? std::to_string(threads).c_str() : "all",
      Join(post_process, ",").c_str());
  for (int size : sizes) {
    DemoOptions demo;
    demo.frames = frames;
    demo.width = demo.height = size;
    Plan plan = MakeDemoPlan(demo);
    plan.post_process = post_process;
    std::vector<Layout> runs(layouts.size());
    for (size_t i = 0; i < layouts.size(); ++i) {
      if (!ParseLayout(layouts[i], plan, spp, root, &runs[i])) {
        std::fprintf(
            stderr,
            "--layouts: %s is not full|compact|residual[/float|residual[/float|residual]]\n",
            layouts[i].c_str());
        return 2;
      }
    }
    // Bytes, from the first repeat (the files are the same in every repeat).
    struct Bytes {
      std::map<std::string, uintmax_t> per_layer;
      uintmax_t total = 0, bundle = 0;
    };
    std::vector<Bytes> bytes(runs.size());
    // The repeats interleave lsds, its floor and Cycles, so that a change in
    // the machine's load lands on all of them; the table gives medians.
    std::vector<Repeat> measured(repeats);
    const fs::path cycles_out = root / ("cycles_" + std::to_string(size));
    uintmax_t cycles_bytes = 0;
    for (int k = 0; k < repeats; ++k) {
      Repeat& repeat = measured[k];
      for (size_t i = 0; i < runs.size(); ++i) {
        const Layout& run = runs[i];
        const double cpu = CpuSeconds(RUSAGE_SELF);
        repeat.generate.push_back(GenerateCollection(plan, run.options));
        repeat.generate_cpu_seconds.push_back(CpuSeconds(RUSAGE_SELF) - cpu);
        if (k == 0) {
          for (const LayerInfo& layer : run.header.layers) {
            bytes[i].per_layer[layer.name] = FolderBytes(run.options.output / layer.name);
            bytes[i].total += bytes[i].per_layer[layer.name];
            if (layer.deep) bytes[i].bundle += bytes[i].per_layer[layer.name];
          }
          bytes[i].total += FolderBytes(run.options.output) - bytes[i].total;  // + JSON
        }
        fs::remove_all(run.options.output);
      }
      MeasureFloor(plan, spp, runs, root, &repeat);
      if (!blender.empty()) {
        const PeerRun cycles = RunCycles(blender, size, frames, spp, threads, cycles_out);
        if (cycles.ran) repeat.cycles_seconds = cycles.seconds;
        repeat.cycles_cpu_seconds = cycles.cpu_seconds;
        if (k == 0) cycles_bytes = cycles.bytes;
        fs::remove_all(cycles_out);
      }
    }
    const double ray_seconds = MedianOver(measured, [](const Repeat& r) { return r.ray_seconds; });

    std::printf("\n%dx%d, %d frames, spp %d\n", size, size, frames, spp);
    std::printf("%-26s %8s %8s %9s %9s %9s %10s %9s %6s %9s %6s %9s %11s\n",
                "layout",
                "s/frame",
                "Mrays/s",
                "render/f",
                "write/f",
                "rays s/f",
                "encode s/f",
                "floor s/f",
                "ratio",
                "steady/f",
                "ratio",
                "MB/frame",
                "w/o bundle");
    std::vector<std::string> paired;  // each repeat's ratio, s/frame / floor
    for (size_t i = 0; i < runs.size(); ++i) {
      auto median = [&](auto value) { return MedianOver(measured, value); };
      const double total = median([&](const Repeat& r) { return r.generate[i].total_seconds; });
      const double encode = median([&](const Repeat& r) { return r.encode_seconds[i]; });
      const double per_frame = total / frames;
      const double floor = (ray_seconds + encode) / frames;
      // steady/f: a frame once the render-while-write pipeline is full
      // (GenerateSummary::steady_seconds_per_frame), the throughput of a long
      // collection; s/frame also carries the first render and the last write.
      const double steady =
          median([&](const Repeat& r) { return r.generate[i].steady_seconds_per_frame; });
      std::printf(
          "%-26s %8.3f %8.2f %9.3f %9.3f %9.3f %10.3f %9.3f %6.2f %9.3f %6.2f %9.2f %11.2f\n",
          runs[i].name.c_str(),
          per_frame,
          median([&](const Repeat& r) {
            return r.generate[i].rays / r.generate[i].total_seconds;
          }) / 1e6,
          median([&](const Repeat& r) { return r.generate[i].render_seconds; }) / frames,
          median([&](const Repeat& r) { return r.generate[i].write_seconds; }) / frames,
          ray_seconds / frames,
          encode / frames,
          floor,
          per_frame / floor,
          steady,
          steady / floor,
          Mb(static_cast<double>(bytes[i].total) / frames),
          Mb(static_cast<double>(bytes[i].total - bytes[i].bundle) / frames));
      std::string line = runs[i].name + ":";
      for (const Repeat& r : measured) {
        const double floor_seconds = r.ray_seconds + r.encode_seconds[i];
        char ratio[64];
        std::snprintf(ratio,
                      sizeof ratio,
                      " %.2f (%.2f s / %.2f s)",
                      r.generate[i].total_seconds / floor_seconds,
                      r.generate[i].total_seconds,
                      floor_seconds);
        line += ratio;
      }
      paired.push_back(line);
    }
    std::printf("medians of %d repeats; each repeat's s/frame / floor: %s\n",
                repeats,
                Join(paired, ", ").c_str());
    std::printf("floor rays: %.2f Mrays/s\n", MedianOver(measured, [](const Repeat& r) {
                                                return r.floor_rays / r.ray_seconds;
                                              }) / 1e6);
    PrintFeatureCosts(plan, spp);
    std::printf("MB per frame per layer:");
    for (const Layout& run : runs) std::printf(" %26s", run.name.c_str());
    std::printf("\n");
    for (const auto& [layer, layer_bytes] : bytes.front().per_layer) {
      std::printf("  %-20s", layer.c_str());
      for (const Bytes& b : bytes)
        std::printf(" %26.2f", Mb(static_cast<double>(b.per_layer.at(layer)) / frames));
      std::printf("\n");
    }
    if (blender.empty()) {
      std::printf("Blender Cycles: not installed (make bench installs it)\n");
      continue;
    }
    std::vector<Repeat> cycles_ran;
    for (const Repeat& r : measured)
      if (r.cycles_seconds) cycles_ran.push_back(r);
    if (cycles_ran.empty()) continue;
    const double cycles_per_frame =
        MedianOver(cycles_ran, [](const Repeat& r) { return *r.cycles_seconds; }) / frames;
    const double lsds_per_frame =
        MedianOver(measured, [](const Repeat& r) { return r.generate.back().total_seconds; }) /
        frames;
    std::printf(
        "Blender Cycles (%s, depth/normal/position/object-index/vector passes, median of %zu): "
        "%.3f s/frame, %.2f MB/frame; lsds %s / Cycles time: %.2f\n",
        blender.c_str(),
        cycles_ran.size(),
        cycles_per_frame,
        Mb(static_cast<double>(cycles_bytes) / frames),
        runs.back().name.c_str(),
        lsds_per_frame / cycles_per_frame);
    // Each repeat's lsds run and Cycles run are a pair, taken one after the
    // other: the median of their ratios, wall and CPU (user + system).
    const double wall_ratio = MedianOver(cycles_ran, [](const Repeat& r) {
      return r.generate.back().total_seconds / *r.cycles_seconds;
    });
    const double cpu_ratio = MedianOver(cycles_ran, [](const Repeat& r) {
      return r.generate_cpu_seconds.back() / r.cycles_cpu_seconds;
    });
    std::printf(
        "paired (median of %zu): lsds / Cycles wall %.3f, CPU %.3f; CPU s/frame lsds %.3f, "
        "Cycles %.3f; lsds cores busy %.2f\n",
        cycles_ran.size(),
        wall_ratio,
        cpu_ratio,
        MedianOver(cycles_ran, [](const Repeat& r) { return r.generate_cpu_seconds.back(); }) /
            frames,
        MedianOver(cycles_ran, [](const Repeat& r) { return r.cycles_cpu_seconds; }) / frames,
        MedianOver(cycles_ran, [](const Repeat& r) {
          return r.generate_cpu_seconds.back() / r.generate.back().total_seconds;
        }));
  }
  fs::remove_all(root);
  return 0;
}
