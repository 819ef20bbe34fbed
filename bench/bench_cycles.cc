// Benchmark of `lsds generate --renderer cycles` (issue 45): the built-in demo scene rendered
//   1. by the reference renderer (lsds generate),
//   2. by `lsds generate --renderer cycles` (scene export + one Blender Cycles render per frame
//      for the rgb and its depth and object index passes + lsds's own render for every truth
//      layer),
//   3. by Blender alone on the exported scene (render_frames.py --no-truth: what a user rendering
//      `lsds export-scene`'s output would run),
// at the same size, samples and frames, printing wall and CPU (user + system, Blender's
// included) seconds per frame and the ratios reference / Blender alone and --renderer cycles /
// Blender alone (aim <= 1.1: the truth adds little). Each figure is the median of --repeats runs
// taking turns.
//
//   bench_cycles [--frames N] [--size WxH] [--spp S] [--threads T] [--repeats R] [--blender PATH]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/stopwatch.h"
#include "generator/cycles/blender.h"
#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/scene_export/scene_export.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"

namespace {

namespace fs = std::filesystem;
using lsds::bench::Clock;
using lsds::bench::CpuSeconds;
using lsds::bench::Seconds;
using namespace lsds;       // NOLINT(google-build-using-namespace): a benchmark's main file
using namespace lsds::gen;  // NOLINT(google-build-using-namespace)

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 4, spp = 16, threads = 0, repeats = 3;
  DemoOptions demo;
  demo.width = 256;
  demo.height = 192;
  std::string blender_flag;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--frames") {
      frames = std::atoi(argv[i + 1]);
    } else if (flag == "--spp") {
      spp = std::atoi(argv[i + 1]);
    } else if (flag == "--threads") {
      threads = std::atoi(argv[i + 1]);
    } else if (flag == "--repeats") {
      repeats = std::max(1, std::atoi(argv[i + 1]));
    } else if (flag == "--size") {
      const std::vector<std::string> size = Split(argv[i + 1], 'x');
      if (size.size() == 2) {
        demo.width = std::atoi(size[0].c_str());
        demo.height = std::atoi(size[1].c_str());
      }
    } else if (flag == "--blender") {
      blender_flag = argv[i + 1];
    } else {
      std::fprintf(stderr,
                   "usage: bench_cycles [--frames N] [--size WxH] [--spp S] [--threads T] "
                   "[--repeats R] [--blender PATH]\n");
      return 2;
    }
  }
  fs::path blender;
  try {
    blender = FindBlender(blender_flag);
  } catch (const std::exception& e) {
    std::printf("bench_cycles: skipped: %s\n", e.what());  // make bench goes on
    return 0;
  }
  const ThreadLimit control(threads);
  demo.frames = frames;
  const Plan plan = MakeDemoPlan(demo);
  const fs::path root = fs::temp_directory_path() / "lsds_bench_cycles";
  fs::remove_all(root);
  fs::create_directories(root);
  std::printf(
      "lsds generate --renderer cycles benchmark: demo scene (%zu objects), %dx%d, %d frames, "
      "spp %d, threads %s, Blender %s\n",
      plan.objects.size(),
      demo.width,
      demo.height,
      frames,
      spp,
      threads > 0 ? std::to_string(threads).c_str() : "all",
      BlenderVersion(blender).c_str());

  std::vector<double> reference, cycles, cycles_export, cycles_blender, alone, alone_export;
  std::vector<double> reference_cpu, cycles_cpu, alone_cpu;
  double depth_error = 0, id_share = 0;
  for (int r = 0; r < repeats; ++r) {
    GenerateOptions options;
    options.spp = spp;
    options.threads = threads;
    options.progress = false;
    options.force = true;
    options.output = root / "reference";
    Clock::time_point t0 = Clock::now();
    double cpu0 = CpuSeconds();
    GenerateCollection(plan, options);
    reference.push_back(Seconds(t0) / frames);
    reference_cpu.push_back((CpuSeconds() - cpu0) / frames);

    options.output = root / "cycles";
    options.renderer = Renderer::kCycles;
    options.blender = blender.string();
    t0 = Clock::now();
    cpu0 = CpuSeconds();
    const GenerateSummary summary = GenerateCollection(plan, options);
    cycles.push_back(Seconds(t0) / frames);
    cycles_cpu.push_back((CpuSeconds() - cpu0) / frames);
    cycles_export.push_back(summary.export_seconds / frames);
    cycles_blender.push_back(summary.cycles_seconds / frames);
    const nlohmann::json agreement = AgreementSummaryJson(summary.cycles_agreement);
    depth_error = std::max(depth_error, agreement["max_relative_depth_error"].get<double>());
    id_share = std::max(id_share, agreement["max_id_mismatch_share"].get<double>());

    // Blender alone on the exported scene (the export itself timed apart).
    SceneExportOptions export_options;
    export_options.output = root / "export";
    export_options.force = true;
    t0 = Clock::now();
    ExportScenes(plan, export_options);
    alone_export.push_back(Seconds(t0) / frames);
    std::vector<int64_t> indices;
    for (const PlannedFrame& f : plan.frames) indices.push_back(f.index);
    fs::remove_all(root / "alone");
    t0 = Clock::now();
    cpu0 = CpuSeconds();
    RenderWithCycles(blender,
                     root / "export",
                     root / "alone",
                     indices,
                     {spp, threads, false, /*truth_passes=*/false},
                     root / "alone.log");
    alone.push_back(Seconds(t0) / frames);
    alone_cpu.push_back((CpuSeconds() - cpu0) / frames);
  }
  const double blender_alone = Median(alone), blender_alone_cpu = Median(alone_cpu);
  std::printf(
      "\n| %dx%d, %d spp, %d frames | s/frame | / Blender alone | CPU s/frame | / Blender alone "
      "|\n",
      demo.width,
      demo.height,
      spp,
      frames);
  std::printf("|---|---|---|---|---|\n");
  std::printf("| reference renderer (lsds generate) | %.3f | %.2f | %.3f | %.2f |\n",
              Median(reference),
              Median(reference) / blender_alone,
              Median(reference_cpu),
              Median(reference_cpu) / blender_alone_cpu);
  std::printf("| lsds generate --renderer cycles | %.3f | %.2f | %.3f | %.2f |\n",
              Median(cycles),
              Median(cycles) / blender_alone,
              Median(cycles_cpu),
              Median(cycles_cpu) / blender_alone_cpu);
  std::printf("|   of which scene export | %.3f | | | |\n", Median(cycles_export));
  std::printf(
      "|   of which Blender's run (rgb with its truth passes, beside lsds's render) | %.3f | | | "
      "|\n",
      Median(cycles_blender));
  std::printf("| Blender alone on the export (rgb only) | %.3f | 1 | %.3f | 1 |\n",
              blender_alone,
              blender_alone_cpu);
  std::printf("| lsds export-scene (for reference) | %.3f | | | |\n", Median(alone_export));
  std::printf(
      "\nCycles against lsds's truth: max relative depth error %.3g, max id mismatch "
      "share %.4f\n",
      depth_error,
      id_share);
  std::printf("Each repeat's ratio --renderer cycles / Blender alone:");
  for (size_t r = 0; r < cycles.size(); ++r) std::printf(" %.2f", cycles[r] / alone[r]);
  std::printf("; in CPU seconds:");
  for (size_t r = 0; r < cycles.size(); ++r) std::printf(" %.2f", cycles_cpu[r] / alone_cpu[r]);
  std::printf("\n");
  fs::remove_all(root);
  return 0;
}
