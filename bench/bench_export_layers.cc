// Benchmark of lsds export-layers: frames/s and MB/s written for each target
// (npy, tiff, png16) next to the floor, reading and decoding the same EXRs
// alone with the same parallelism.
//
//   bench_export_layers [--size 256] [--frames 20] [--repeat 3] [--work DIR]
//
// Issue-sized run: --size 1024 --frames 100. The synthetic collection is
// rendered once into DIR (default /tmp/lsds_bench_export_layers_SIZE_FRAMES)
// and reused by later runs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "export_layers/export_layers.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "synth/synthetic_collection.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

// Best wall time of `repeat` runs (the machine may be shared: the best run is
// the least disturbed).
double Seconds(const std::function<void()>& fn, int repeat) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    best = std::min(
        best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("lsds export-layers benchmark");
  int size = 256, frames = 20, repeat = 3;
  std::string work;
  app.add_option("--size", size, "frame width and height (pixels)");
  app.add_option("--frames", frames, "frames of the collection");
  app.add_option("--repeat", repeat, "repetitions (best is kept)");
  app.add_option("--work", work, "folder for the synthetic collection (reused when present)");
  CLI11_PARSE(app, argc, argv);
  if (work.empty()) {
    work = (fs::temp_directory_path() /
            ("lsds_bench_export_layers_" + std::to_string(size) + "_" + std::to_string(frames)))
               .string();
  }
  const fs::path collection = fs::path(work) / "collection";
  // The flat truth layers (no rgb, no deep bundle): what png16 can hold, so
  // every target exports the same layers.
  const std::vector<std::string> layers = {
      "classid", "instanceid", "depth", "normal", "shadow", "motion"};
  if (!fs::exists(collection / "collection.json")) {
    std::printf("rendering a %dx%d synthetic collection of %d frames into %s ...\n",
                size,
                size,
                frames,
                collection.c_str());
    synth::Spec spec = synth::CircleSpec(frames, size, size);
    spec.samples_per_axis = 1;
    spec.layers = layers;
    fs::remove_all(collection);
    fs::create_directories(work);
    synth::WriteCollection(collection, spec);
  }
  const CollectionReader reader(collection);
  int64_t exr_bytes = 0;
  for (const std::string& layer : layers)
    for (const auto& entry : fs::directory_iterator(collection / layer))
      exr_bytes += static_cast<int64_t>(entry.file_size());
  std::printf(
      "lsds export-layers benchmark: %d frames of %dx%d, layers %s, %.1f MB "
      "of EXR\n",
      frames,
      size,
      size,
      "classid,instanceid,depth,normal,shadow,motion",
      exr_bytes / 1e6);

  // Floor: stream collection.json and decode every EXR the export reads, in
  // the same parallel batches.
  const size_t batch = std::max<size_t>(2, 2 * std::thread::hardware_concurrency());
  const double floor = Seconds(
      [&] {
        reader.ParallelForEachFrame(
            [&](const Frame& frame) {
              for (const std::string& layer : layers)
                exr::ReadFlatExr(reader.LayerPath(frame, layer));
            },
            batch);
      },
      repeat);
  std::printf("  %-34s %9.1f ms  %8.1f frames/s  %8.1f MB/s EXR read %8s MB/s written  x1.00\n",
              "floor: read + decode the EXRs",
              floor * 1e3,
              frames / floor,
              exr_bytes / floor / 1e6,
              "-");

  for (const layer_export::Target target :
       {layer_export::Target::kNpy, layer_export::Target::kTiff, layer_export::Target::kPng16}) {
    layer_export::ExportOptions options;
    options.collection = collection;
    options.output = fs::path(work) / (std::string("out_") + layer_export::TargetName(target));
    options.target = target;
    options.layers = layers;
    options.depth_step = 0.001;
    options.force = true;
    layer_export::ExportSummary summary;
    const double seconds = Seconds([&] { summary = layer_export::ExportLayers(options); }, repeat);
    char label[64];
    std::snprintf(label, sizeof label, "export-layers --to %s", layer_export::TargetName(target));
    std::printf(
        "  %-34s %9.1f ms  %8.1f frames/s  %8.1f MB/s EXR read %8.1f MB/s written  x%.2f floor\n",
        label,
        seconds * 1e3,
        frames / seconds,
        exr_bytes / seconds / 1e6,
        summary.bytes / seconds / 1e6,
        seconds / floor);
  }
  return 0;
}
