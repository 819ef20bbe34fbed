// Benchmark of `import lsds` (docs/python.md, "Performance"), in one run:
//   1. frames/s through lsds.torch's FrameDataset in a DataLoader with 0 and 2 workers
//      (bench/peers/torch_frames.py) against the floor: the same layers of the same frames
//      decoded by lsds's C++ reader (CollectionReader::ReadFlatLayer, which the module calls) in
//      one process on one thread; aim >= 0.8x the floor;
//   2. the bytes of one frame of the demo at 1024x1024, 4 spp: lsds's default layers, the same
//      with --compact, and Blender Cycles' multilayer EXR of the same frame (the scene of
//      `lsds export-scene`, rendered by generator/cycles/render_frames.py --all-passes: Combined,
//      Depth, Normal, Position, Object Index and Vector); aims <= 0.6x and <= 0.3x.
//
//   bench_python [--size 512] [--frames 16] [--layers rgb,depth,...] [--repeats 3]
//                [--bytes-size 1024] [--spp 4] [--blender PATH|none] [--python PYTHON]
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/stopwatch.h"
#include "generator/cycles/blender.h"
#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/scene_export/scene_export.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/process.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"
#include "tests/build_paths.h"

namespace {

namespace fs = std::filesystem;
using lsds::bench::Clock;
using lsds::bench::Seconds;
using namespace lsds;       // NOLINT(google-build-using-namespace): a benchmark's main file
using namespace lsds::gen;  // NOLINT(google-build-using-namespace)

// What `command` prints on stdout; "" when it fails.
std::string Output(const std::string& command) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return out;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe.get()) != nullptr) out += buffer.data();
  return out;
}

std::string Quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// The demo at `size` x `size`: `frames` frames, every layer, `compact` layouts or the defaults.
void GenerateDemo(const fs::path& out, int size, int frames, int spp, bool compact) {
  DemoOptions demo;
  demo.width = demo.height = size;
  demo.frames = frames;
  GenerateOptions options;
  options.output = out;
  options.spp = spp;
  options.force = true;
  options.progress = false;
  if (compact) options.layouts.UseCompact();
  GenerateCollection(MakeDemoPlan(demo), options);
}

// Part 1: the floor and the DataLoader's frames/s.
void FramesPerSecond(const fs::path& root,
                     int size,
                     int frames,
                     const std::string& layers,
                     int repeats,
                     const std::string& python) {
  const fs::path collection = root / ("demo_" + std::to_string(size));
  GenerateDemo(collection, size, frames, 4, false);
  const CollectionReader reader(collection);
  const std::vector<std::string> names = Split(layers, ',');
  const auto decode = [&](const Frame& frame) {
    for (const std::string& name : names) {
      const LayerInfo* layer = reader.header().FindLayer(name);
      std::vector<std::string> channels;
      for (const LayerChannel& c : layer->channels) channels.push_back(c.name);
      reader.ReadFlatLayer(frame, name, channels);
    }
  };
  // The floor on `threads` threads (TBB capped, as lsds.open's threads=1 caps a decode): frames
  // one after the other on one thread, in parallel batches on two (as two DataLoader workers).
  const auto floor_frames_per_second = [&](int threads) {
    const ThreadLimit limit(threads);
    double best = 1e300;
    for (int r = 0; r <= repeats; ++r) {  // the first pass fills the page cache, as the peer's
      const Clock::time_point start = Clock::now();
      if (threads == 1) {
        reader.ForEachFrame(decode);
      } else {
        reader.ParallelForEachFrame(decode, 2 * static_cast<size_t>(threads));
      }
      if (r > 0) best = std::min(best, Seconds(start));
    }
    return frames / best;
  };
  const double floor1 = floor_frames_per_second(1), floor2 = floor_frames_per_second(2);
  const std::string command =
      "PYTHONPATH=" + Quoted(fs::path(testing::BinaryDir()) / "python") + " " + python + " " +
      Quoted(fs::path(testing::SourceDir()) / "bench/peers/torch_frames.py") + " " +
      Quoted(collection) + " --layers " + layers + " --workers 0,2 --repeats " +
      std::to_string(repeats);
  const std::string printed = Output(command);
  std::printf("\n| %dx%d demo, %d frames, layers %s | frames/s | / floor |\n",
              size,
              size,
              frames,
              layers.c_str());
  std::printf("|---|---|---|\n");
  std::printf("| floor: lsds's C++ reader, one process, one thread | %.1f | 1 |\n", floor1);
  std::printf("| floor: lsds's C++ reader, one process, two threads | %.1f | 1 |\n", floor2);
  nlohmann::json result;
  try {
    result = nlohmann::json::parse(printed);
  } catch (const nlohmann::json::exception&) {
    std::printf("lsds.torch: no result (is PyTorch installed for %s?): %s\n",
                python.c_str(),
                printed.c_str());
    return;
  }
  // No worker: the main process decodes on one thread; two workers: two processes.
  for (const auto& [workers, rate] : result["workers"].items()) {
    const double floor = workers == "0" ? floor1 : floor2;
    std::printf("| lsds.torch FrameDataset, DataLoader num_workers=%s | %.1f | %.2f of the %s |\n",
                workers.c_str(),
                rate.get<double>(),
                rate.get<double>() / floor,
                workers == "0" ? "one-thread floor" : "two-thread floor");
  }
}

// The bytes of frame `index`'s files: every layer, and without the deep bundle.
std::pair<double, double> FrameBytes(const fs::path& collection, int64_t index) {
  const CollectionReader reader(collection);
  double all = 0, flat = 0;
  reader.ForEachFrame([&](const Frame& frame) {
    if (frame.index != index) return;
    for (const LayerInfo& layer : reader.header().layers) {
      const double bytes = static_cast<double>(fs::file_size(reader.LayerPath(frame, layer.name)));
      all += bytes;
      if (!layer.deep) flat += bytes;
    }
  });
  return {all, flat};
}

// Part 2: bytes of frame 1 (it has motion) of the demo, lsds against Cycles.
void BytesPerFrame(const fs::path& root, int size, int spp, const std::string& blender_flag) {
  const fs::path plain = root / "bytes_default", compact = root / "bytes_compact";
  GenerateDemo(plain, size, 2, spp, false);
  GenerateDemo(compact, size, 2, spp, true);
  const auto [plain_all, plain_flat] = FrameBytes(plain, 1);
  const auto [compact_all, compact_flat] = FrameBytes(compact, 1);
  double cycles = 0;
  std::string blender_version;
  if (blender_flag != "none") {
    try {
      const fs::path blender = FindBlender(blender_flag);
      blender_version = BlenderVersion(blender);
      DemoOptions demo;
      demo.width = demo.height = size;
      demo.frames = 2;
      SceneExportOptions export_options;
      export_options.output = root / "export";
      export_options.force = true;
      ExportScenes(MakeDemoPlan(demo), export_options);
      const fs::path rendered = root / "cycles";
      fs::remove_all(rendered);
      const std::vector<std::string> command = {blender.string(),
                                                "-b",
                                                "--factory-startup",
                                                "-noaudio",
                                                "--python",
                                                CyclesScript().string(),
                                                "--",
                                                (root / "export").string(),
                                                rendered.string(),
                                                "--frames",
                                                "1",
                                                "--samples",
                                                std::to_string(spp),
                                                "--no-truth",
                                                "--all-passes"};
      if (RunProcess(command, root / "cycles.log") == 0)
        cycles = static_cast<double>(fs::file_size(rendered / "000001_rgb.exr"));
      else
        std::printf("Blender failed: see %s\n", (root / "cycles.log").c_str());
    } catch (const std::exception& e) {
      std::printf("Cycles: skipped: %s\n", e.what());
    }
  }
  std::printf(
      "\n| demo frame 1, %dx%d, %d spp | MB | without the bundle | / Cycles |\n", size, size, spp);
  std::printf("|---|---|---|---|\n");
  const auto row = [&](const char* what, double all, double flat) {
    std::printf("| %s | %.2f | %.2f | ", what, all / 1e6, flat / 1e6);
    if (cycles > 0) {
      std::printf("%.2f (%.2f without the bundle) |\n", all / cycles, flat / cycles);
    } else {
      std::printf("- |\n");
    }
  };
  row("lsds generate (default: float worldposition and motion)", plain_all, plain_flat);
  row("lsds generate --compact", compact_all, compact_flat);
  if (cycles > 0) {
    std::printf(
        "| Blender Cycles %s multilayer EXR (Combined, Depth, Normal, Position, "
        "IndexOB, Vector; ZIP) | %.2f | | 1 |\n",
        blender_version.c_str(),
        cycles / 1e6);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_python: lsds.torch frames/s against the C++ floor; bytes per frame "
      "against Blender Cycles"};
  int size = 512, frames = 16, repeats = 3, bytes_size = 1024, spp = 4;
  std::string layers = "rgb,depth,normal,worldposition,motion,instanceid";
  std::string blender = "",
              python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string work = (fs::temp_directory_path() / "lsds_bench_python").string();
  app.add_option("--size", size, "frames/s: the demo's size, SIZE x SIZE (512)");
  app.add_option("--frames", frames, "frames/s: frames of the demo (16)");
  app.add_option("--layers", layers, "frames/s: the layers decoded");
  app.add_option("--repeats", repeats, "best of R passes (3)");
  app.add_option("--bytes-size", bytes_size, "bytes: the demo's size (1024; 0: skip)");
  app.add_option("--spp", spp, "bytes: samples per pixel (4)");
  app.add_option("--blender", blender, "Blender for the Cycles peer (default: on PATH; none)");
  app.add_option("--python", python, "the Python with PyTorch (default /usr/bin/python3)");
  app.add_option("--work", work, "scratch folder (removed at the end)");
  CLI11_PARSE(app, argc, argv);
  const fs::path root = work;
  fs::create_directories(root);
  std::printf("import lsds benchmark (%s)\n", python.c_str());
  if (frames > 0) FramesPerSecond(root, size, frames, layers, repeats, python);
  if (bytes_size > 0) BytesPerFrame(root, bytes_size, spp, blender);
  fs::remove_all(root);
  return 0;
}
