// Benchmark of the built-in UAV assets and image textures (docs/generator.md,
// "Performance"): the render time per frame of the demo scene as it is drawn
// today (barrels, tires, jerrycans, rocks, bushes, people, cubes), of the same
// layout drawn with the vehicle/tree/figure/crate meshes, and with every
// cube replaced by a textured OBJ box (a 256 x 256 PNG base-colour map), each
// as a ratio to today's frame time. Also the floor: every object a cube.
// Render only (scene build + integrator), no EXR writing.
//
//   bench_assets [--frames N] [--size S] [--spp K] [--rounds R]
//
// The variants run interleaved R times (default 3) and each reports its
// fastest round, which damps the noise of a shared machine.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "generator/demo_plan.h"
#include "generator/render/integrator.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace lsds;
using namespace lsds::gen;

namespace {

// A unit box with a texture coordinate square on each face and a checker map.
std::string WriteTexturedBox(const fs::path& dir) {
  fs::create_directories(dir);
  cv::Mat image(256, 256, CV_8UC3);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      image.at<cv::Vec3b>(y, x) =
          ((x / 32 + y / 32) % 2) ? cv::Vec3b(40, 90, 200) : cv::Vec3b(220, 220, 210);
  cv::imwrite((dir / "checker.png").string(), image);
  std::ofstream(dir / "box.mtl") << "newmtl m\nmap_Kd checker.png\n";
  std::ofstream obj(dir / "box.obj");
  obj << "mtllib box.mtl\nusemtl m\n";
  for (int k = 0; k < 8; ++k)
    obj << "v " << ((k & 1) ? 0.5 : -0.5) << ' ' << ((k & 2) ? 0.5 : -0.5) << ' '
        << ((k & 4) ? 0.5 : -0.5) << '\n';
  obj << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  const int faces[6][4] = {
      {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces)
    obj << "f " << f[0] + 1 << "/1 " << f[1] + 1 << "/2 " << f[2] + 1 << "/3 " << f[3] + 1
        << "/4\n";
  return (dir / "box.obj").string();
}

double SecondsPerFrame(const Plan& plan, int spp) {
  static EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);  // per plan, outside the frame time
  const Sky sky(plan);
  RenderSettings settings;
  settings.sampler = {spp, 1.0, plan.seed};
  const Clock::time_point start = Clock::now();
  for (const PlannedFrame& frame : plan.frames) {
    const WorldState world = WorldAt(plan, frame);
    const RenderScene scene(device, plan, assets, world);
    const Film film = RenderFrame(scene, sky, frame, PreviousView(), settings);
    if (film.flat.empty()) std::abort();
  }
  return std::chrono::duration<double>(Clock::now() - start).count() /
         static_cast<double>(plan.frames.size());
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 4, size = 256, spp = 4, rounds = 3;
  for (int i = 1; i < argc; i += 2) {
    if (i + 1 == argc) {
      std::fprintf(stderr, "bench_assets: %s needs a value\n", argv[i]);
      return 2;
    }
    if (!std::strcmp(argv[i], "--frames"))
      frames = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--size"))
      size = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--spp"))
      spp = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--rounds"))
      rounds = std::max(1, std::atoi(argv[i + 1]));
    else {
      std::fprintf(stderr, "usage: bench_assets [--frames N] [--size S] [--spp K] [--rounds R]\n");
      return 2;
    }
  }
  DemoOptions options;
  options.frames = frames;
  options.width = options.height = size;
  const Plan today = MakeDemoPlan(options);
  // The same layout (positions, sizes per slot) drawn with other classes.
  auto with_classes = [&today](const std::vector<std::string>& classes) {
    Plan plan = today;
    for (size_t i = 0; i < plan.objects.size(); ++i)
      plan.objects[i].class_name = classes[i % classes.size()];
    return plan;
  };
  const fs::path dir = fs::temp_directory_path() / "lsds_bench_assets";
  const std::string textured_box = WriteTexturedBox(dir);
  const struct {
    const char* label;
    Plan plan;
  } runs[] = {
      {"cubes (floor)", with_classes({"cube"})},
      {"today (demo)", today},
      {"new builtins", with_classes({"car", "truck", "tree", "person", "crate", "rock", "barrel"})},
      {"textured OBJ",
       with_classes({"barrel", "tire", "jerrycan", "rock", "bush", "person", textured_box})},
  };
  std::printf("demo layout, %d objects, %dx%d, %d frames, spp %d\n",
              static_cast<int>(today.objects.size()),
              size,
              size,
              frames,
              spp);
  std::printf("%-16s %10s %16s\n", "scene", "s/frame", "ratio to today");
  double reference = 0;
  std::vector<double> seconds(std::size(runs), 1e300);
  for (int round = 0; round < rounds; ++round)
    for (size_t i = 0; i < seconds.size(); ++i)
      seconds[i] = std::min(seconds[i], SecondsPerFrame(runs[i].plan, spp));
  reference = seconds[1];
  for (size_t i = 0; i < seconds.size(); ++i)
    std::printf("%-16s %10.3f %16.2f\n", runs[i].label, seconds[i], seconds[i] / reference);
  fs::remove_all(dir);
  return 0;
}
