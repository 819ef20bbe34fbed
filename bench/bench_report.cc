// bench_report: frames/s of `lsds report` on a synthetic collection (lsds
// synth's circle of nadir frames), next to the floor: streaming collection.json
// and decoding every frame's depth layer, which the distributions need for the
// altitude and GSD at the image centre. Prints the time of the streaming pass
// (distributions + sample), of the whole page (plus the sampled frames' layers
// drawn and encoded), frames/s and the ratio to the floor.
//
//   bench_report [--frames 300] [--size 320x240] [--sample 24]
//                [--layer-frames 4] [--dir PATH]
// The synthetic collection is written once into
// /tmp/lsds_bench_report_FRAMES_SIZE (or --dir) and reused.
#include <chrono>
#include <cstdio>

#include <tbb/parallel_for.h>
#include <CLI/CLI.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "report/report.h"
#include "synth/synthetic_collection.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

double Seconds(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The same frame stream and batching as the report's pass, decoding only.
double Floor(const fs::path& root) {
  const CollectionReader reader(root);
  const auto start = std::chrono::steady_clock::now();
  std::vector<Frame> batch;
  auto flush = [&] {
    tbb::parallel_for(size_t{0}, batch.size(), [&](size_t i) {
      exr::ReadFlatExr(reader.LayerPath(batch[i], "depth"), {"Z"});
    });
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& frame) {
    batch.push_back(frame);
    if (batch.size() == 32) flush();
  });
  flush();
  return Seconds(start);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Benchmark of lsds report on a synthetic collection.");
  int frames = 300, width = 320, height = 240;
  std::string size = "320x240", dir;
  size_t sample = 24, layer_frames = 4;
  app.add_option("--frames", frames)->check(CLI::PositiveNumber);
  app.add_option("--size", size, "WIDTHxHEIGHT");
  app.add_option("--sample", sample, "frames on the contact sheet");
  app.add_option("--layer-frames", layer_frames, "frames with every layer");
  app.add_option("--dir", dir, "where to write the collection (default: temp)");
  CLI11_PARSE(app, argc, argv);
  if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2) {
    std::fprintf(stderr, "--size must be WIDTHxHEIGHT\n");
    return 2;
  }
  const fs::path root =
      dir.empty()
          ? fs::temp_directory_path() / ("lsds_bench_report_" + std::to_string(frames) + "_" + size)
          : fs::path(dir);
  if (!fs::exists(root / "collection.json")) {
    fs::remove_all(root);
    const auto start = std::chrono::steady_clock::now();
    synth::Spec spec = synth::CircleSpec(frames, width, height);
    synth::WriteCollection(root, spec);
    std::printf("synth collection  %d frames %dx%d in %.2f s (%s)\n",
                frames,
                width,
                height,
                Seconds(start),
                root.c_str());
  }
  Floor(root);  // warm the page cache
  const double floor = Floor(root);

  report::ReportOptions options;
  options.collection = root;
  options.output = root.parent_path() / (root.filename().string() + ".html");
  options.sample = sample;
  options.layer_frames = layer_frames;
  options.force = true;
  auto start = std::chrono::steady_clock::now();
  {
    const CollectionReader reader(root);
    report::CollectReportData(reader, options);
  }
  const double pass = Seconds(start);
  start = std::chrono::steady_clock::now();
  const report::ReportResult result = report::WriteReport(options);
  const double whole = Seconds(start);

  std::printf("floor (stream + decode depth)  %.3f s  %8.1f frames/s\n", floor, frames / floor);
  std::printf("report pass (distributions)    %.3f s  %8.1f frames/s  %.2fx floor\n",
              pass,
              frames / pass,
              pass / floor);
  std::printf(
      "report page (+%zu thumbnails, %zu layer strips)  %.3f s  %8.1f "
      "frames/s  %.2fx floor  %.0f KiB\n",
      result.sampled,
      layer_frames,
      whole,
      frames / whole,
      whole / floor,
      result.bytes / 1024.0);
  fs::remove(options.output);
  return 0;
}
