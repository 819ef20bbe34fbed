// Benchmark of lsds backproject: points/s for one frame and for a fused run of
// many frames, next to the floor (decoding the depth EXR), and Open3D's
// create_from_depth_image on the same depth when python3 with open3d is
// available.
//
//   bench_backproject [--size 256] [--frames 20] [--voxel 0.05] [--repeat 5]
//                     [--work DIR] [--python /usr/bin/python3] [--no-open3d]
//
// Issue-sized run: --size 1024 --frames 100. The synthetic collection is
// rendered once into DIR (default /tmp/lsds_bench_backproject_SIZE_FRAMES) and
// reused by later runs.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "backproject/backproject.h"
#include "backproject/backproject_run.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "synth/synthetic_collection.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double last_cpu = 0;  // CPU seconds (all threads) of the best repetition of the
                      // last Seconds() call

// Best wall time of `repeat` runs (the machine may be shared: the best run is
// the least disturbed).
double Seconds(const std::function<void()>& fn, int repeat) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const double cpu = CpuSeconds();
    const auto start = std::chrono::steady_clock::now();
    fn();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (wall < best) best = wall, last_cpu = CpuSeconds() - cpu;
  }
  return best;
}

double floor_cpu = 1;  // CPU seconds of the floor the following rows refer to

void Row(const char* what, double points, double seconds, double floor_seconds, double cpu = -1) {
  std::printf("  %-46s %9.2f ms  %8.1f Mpoints/s  x%.2f floor",
              what,
              seconds * 1e3,
              points / seconds / 1e6,
              seconds / floor_seconds);
  if (cpu >= 0) {
    std::printf("  cpu %8.2f ms  x%.2f floor cpu", cpu * 1e3, cpu / floor_cpu);
  }
  std::printf("\n");
}

const char* kOpen3dScript = R"(
import sys, time, numpy as np, open3d as o3d
path, w, h, fx, fy, cx, cy, repeat = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), *map(float, sys.argv[4:8]), int(sys.argv[8])
depth = np.fromfile(path, dtype=np.float32).reshape(h, w)
depth[~np.isfinite(depth)] = 0
image = o3d.geometry.Image(depth)
color = o3d.geometry.Image(np.zeros((h, w, 3), dtype=np.uint8))
# Open3D puts pixel centres at integer coordinates: shift the principal point by half a pixel.
intrinsic = o3d.camera.PinholeCameraIntrinsic(w, h, fx, fy, cx - 0.5, cy - 0.5)
extrinsic = np.eye(4)
def timed(fn):
    best, best_cpu, out = 1e300, 0, None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        wall = time.perf_counter() - t
        if wall < best: best, best_cpu = wall, time.process_time() - c
    return best, best_cpu, out
depth_only = timed(lambda: o3d.geometry.PointCloud.create_from_depth_image(image, intrinsic, extrinsic, depth_scale=1.0, depth_trunc=1e9))
def rgbd():
    rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(color, image, depth_scale=1.0, depth_trunc=1e9, convert_rgb_to_intensity=False)
    return o3d.geometry.PointCloud.create_from_rgbd_image(rgbd, intrinsic, extrinsic)
with_colour = timed(rgbd)
print(len(depth_only[2].points), depth_only[0], depth_only[1], with_colour[0], with_colour[1])
)";

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("lsds backproject benchmark");
  int size = 256, frames = 20, repeat = 5;
  double voxel = 0.05;
  std::string work, python = "/usr/bin/python3";
  bool no_open3d = false;
  app.add_option("--size", size, "frame width and height (pixels)");
  app.add_option("--frames", frames, "frames of the fused run");
  app.add_option("--voxel", voxel, "voxel size of the fused run (m); 0 = no downsampling");
  app.add_option("--repeat", repeat, "repetitions of the single-frame timings (best is kept)");
  app.add_option("--work", work, "folder for the synthetic collection (reused when present)");
  app.add_option("--python", python, "python with open3d");
  app.add_flag("--no-open3d", no_open3d, "skip the Open3D comparison");
  CLI11_PARSE(app, argc, argv);
  if (work.empty()) {
    work = (fs::temp_directory_path() /
            ("lsds_bench_backproject_" + std::to_string(size) + "_" + std::to_string(frames)))
               .string();
  }
  const fs::path collection = fs::path(work) / "collection";
  if (!fs::exists(collection / "collection.json")) {
    std::printf("rendering a %dx%d synthetic collection of %d frames into %s ...\n",
                size,
                size,
                frames,
                collection.c_str());
    synth::Spec spec = synth::DefaultSpec();
    spec.width = spec.height = size;
    spec.samples_per_axis = 1;
    spec.layers = {"rgb", "classid", "instanceid", "depth"};
    spec.cam_from_world.clear();
    // A nadir pass at 20 m, 0.2 m between frames: consecutive frames overlap by
    // ~99 %.
    for (int k = 0; k < frames; ++k)
      spec.cam_from_world.push_back(synth::NadirCamFromWorld({-10 + 0.2 * k, 0, 20}));
    fs::remove_all(collection);
    fs::create_directories(work);
    synth::WriteCollection(collection, spec);
  }
  const CollectionReader reader(collection);
  Frame first;
  bool have = false;
  reader.ForEachFrame([&](const Frame& f) {
    if (!have) first = f, have = true;
  });
  const fs::path depth_path = reader.LayerPath(first, "depth");
  const double pixels = static_cast<double>(size) * size;

  std::printf(
      "lsds backproject benchmark: %dx%d frames (%.2f Mpixels), %d frames "
      "fused, voxel %g m\n",
      size,
      size,
      pixels / 1e6,
      frames,
      voxel);

  // Floor: decoding the depth EXR.
  exr::FlatImage depth;
  const double floor = Seconds([&] { depth = exr::ReadFlatExr(depth_path, {"Z"}); }, repeat);
  std::printf("one frame:\n");
  floor_cpu = last_cpu;
  const double single_floor_cpu = floor_cpu;
  Row("floor: decode depth EXR", pixels, floor, floor, last_cpu);

  // The arithmetic alone, on decoded depth (what Open3D's
  // create_from_depth_image does).
  pointcloud::FrameLayers layers;
  layers.width = layers.height = size;
  layers.depth = depth.Get("Z").floats.data();
  pointcloud::FramePose pose;
  pose.camera = first.camera.intrinsics;
  Eigen::Affine3d cam_from_world = Eigen::Affine3d::Identity();
  cam_from_world.linear() = first.camera.cam_from_world_rotation;
  cam_from_world.translation() = first.camera.cam_from_world_translation;
  pose.out_from_cam = cam_from_world.inverse();
  pointcloud::PointCloud cloud;
  const double core = Seconds(
      [&] {
        cloud.points.clear();
        cloud.points.shrink_to_fit();
        pointcloud::BackprojectFrame(layers, pose, 1, &cloud);
      },
      repeat);
  const double core_cpu = last_cpu;
  const double points = static_cast<double>(cloud.points.size());
  Row("back-projection only (decoded depth, xyz)", points, core, floor, last_cpu);

  auto run =
      [&](bool attributes, const fs::path& out, int64_t begin, int64_t end, bool fuse, double v) {
        pointcloud::BackprojectOptions options;
        options.collection = collection;
        options.output = out;
        options.fuse = fuse;
        options.voxel = v;
        options.colors = options.labels = attributes;
        options.frames.begin = begin;
        options.frames.end = end;
        options.force = true;
        return pointcloud::RunBackproject(options);
      };
  const fs::path out_dir = fs::path(work) / "out";
  fs::create_directories(out_dir);
  const double e2e_xyz = Seconds([&] { run(false, out_dir / "one.pcd", 0, 1, true, 0); }, repeat);
  Row("end to end: depth EXR -> PCD (xyz)", points, e2e_xyz, floor, last_cpu);
  const double e2e_full =
      Seconds([&] { run(true, out_dir / "one_full.pcd", 0, 1, true, 0); }, repeat);
  Row("end to end: + rgb, class, instance -> PCD", points, e2e_full, floor, last_cpu);

  // Many frames fused.
  std::printf("%d frames fused:\n", frames);
  const double floor_all = Seconds(
      [&] {
        reader.ForEachFrame(
            [&](const Frame& f) { exr::ReadFlatExr(reader.LayerPath(f, "depth"), {"Z"}); });
      },
      1);
  floor_cpu = last_cpu;
  Row("floor: decode every depth EXR (1 thread)", pixels * frames, floor_all, floor_all, last_cpu);
  pointcloud::BackprojectSummary summary;
  const double fused =
      Seconds([&] { summary = run(false, out_dir / "fused.pcd", 0, frames, true, voxel); }, 1);
  char label[128];
  std::snprintf(label,
                sizeof label,
                "fused xyz, voxel %g -> %lld points",
                voxel,
                static_cast<long long>(summary.points_written));
  Row(label, static_cast<double>(summary.points_backprojected), fused, floor_all, last_cpu);
  const double fused_full =
      Seconds([&] { summary = run(true, out_dir / "fused_full.pcd", 0, frames, true, voxel); }, 1);
  std::snprintf(label, sizeof label, "fused + rgb/labels, voxel %g", voxel);
  Row(label, static_cast<double>(summary.points_backprojected), fused_full, floor_all, last_cpu);

  // Open3D on the same depth, same camera (camera frame output: extrinsic
  // identity).
  if (no_open3d) {
    std::printf("open3d: skipped (--no-open3d)\n");
    return 0;
  }
  if (std::system((python + " -c 'import open3d' > /dev/null 2>&1").c_str()) != 0) {
    std::printf(
        "open3d: skipped (%s cannot import open3d; Debian: apt-get install "
        "python3-open3d)\n",
        python.c_str());
    return 0;
  }
  const fs::path raw = fs::path(work) / "depth.f32";
  const fs::path script = fs::path(work) / "open3d_bench.py";
  {
    std::ofstream(raw, std::ios::binary)
        .write(reinterpret_cast<const char*>(layers.depth),
               static_cast<std::streamsize>(pixels * sizeof(float)));
    std::ofstream(script) << kOpen3dScript;
  }
  const fs::path result = fs::path(work) / "open3d.txt";
  char command[1024];
  std::snprintf(command,
                sizeof command,
                "%s %s %s %d %d %.17g %.17g %.17g %.17g %d > %s 2>/dev/null",
                python.c_str(),
                script.c_str(),
                raw.c_str(),
                size,
                size,
                pose.camera.fx,
                pose.camera.fy,
                pose.camera.cx,
                pose.camera.cy,
                repeat,
                result.c_str());
  if (std::system(command) != 0) {
    std::printf("open3d: failed to run %s\n", script.c_str());
    return 0;
  }
  long long o3d_points = 0;
  double o3d_depth = 0, o3d_depth_cpu = 0, o3d_rgbd = 0, o3d_rgbd_cpu = 0;
  std::ifstream(result) >> o3d_points >> o3d_depth >> o3d_depth_cpu >> o3d_rgbd >> o3d_rgbd_cpu;
  std::printf("open3d %s (decoded depth, no EXR decode):\n", "0.16");
  floor_cpu = single_floor_cpu;
  Row("create_from_depth_image", static_cast<double>(o3d_points), o3d_depth, floor, o3d_depth_cpu);
  Row("create_from_rgbd_image (+ colour)",
      static_cast<double>(o3d_points),
      o3d_rgbd,
      floor,
      o3d_rgbd_cpu);
  std::printf(
      "lsds back-projection only vs open3d create_from_depth_image: %.2fx "
      "faster (wall), %.2fx (cpu)\n",
      o3d_depth / core,
      o3d_depth_cpu / core_cpu);
  return 0;
}
