// bench_import: frames/s of `lsds import` on synthesized sources, next to the
// floor (reading and decoding the files the importer reads), the ratio, and
// the peak memory (flat in the number of frames: one frame at a time).
//   ue-mrq      tests/import/mrq_fixture.h: multipart EXRs + sidecar; the
//               floor decodes the channels the importer reads
//   kubric      tests/import/kubric_fixture.h: PNG, float TIFF, palette PNG,
//               metadata.json
//   replicator  tests/import/replicator_fixture.h: PNG, .npy, JSON
//   replicator-products  the same as two render products (<product>/<annotator>/)
//   replicator-noseg     no instance segmentation: objects from the 3D boxes,
//               boxes from bounding_box_2d_tight
//   solo        tests/import/solo_fixture.h: PNG, EXR, frame_data.json
// For the file-per-layer sources the floor decodes every file the importer
// opens (PNG/TIFF with OpenCV, .npy, EXR, JSON parse).
//
//   bench_import                       every format, 300 frames at 160x120
//   bench_import --format kubric --frames 300 --size 640x480
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "importers/import_collection.h"
#include "importers/indexed_png.h"
#include "importers/source_exr.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/npy.h"
#include "synth/synthetic_collection.h"
#include "tests/import/kubric_fixture.h"
#include "tests/import/mrq_fixture.h"
#include "tests/import/replicator_fixture.h"
#include "tests/import/solo_fixture.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {
double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
long PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

// The floor of the ue-mrq importer: open every EXR and decode the channels
// it reads.
double MrqFloor(const fs::path& source) {
  double checksum = 0;
  for (const auto& entry : fs::directory_iterator(source)) {
    if (entry.path().extension() != ".exr") continue;
    const import::SourceExr exr(entry.path());
    for (const char* c : {"R",
                          "G",
                          "B",
                          "FinalImageMovieRenderQueue_WorldDepth.R",
                          "CryptoActor00.R",
                          "CryptoActor00.G"})
      checksum += exr.ReadFloat(c)[0];
  }
  return checksum;
}

// The floor of the file-per-layer importers: decode every file they read
// (bounding_box_2d_tight only when there is no instance segmentation to derive
// the boxes from).
double FileFloor(const fs::path& source, bool reads_tight_boxes) {
  double checksum = 0;
  for (const auto& entry : fs::recursive_directory_iterator(source)) {
    if (!entry.is_regular_file()) continue;
    const fs::path& p = entry.path();
    const std::string name = p.filename().string();
    // Files the importers do not open.
    const bool tight =
        name.rfind("bounding_box_2d_tight", 0) == 0 && name.find("labels") == std::string::npos;
    if ((name.find("bounding_box_2d") != std::string::npos && !(reads_tight_boxes && tight)) ||
        name == "data_ranges.json")
      continue;
    const std::string ext = p.extension().string();
    if (name.rfind("segmentation_", 0) == 0 && ext == ".png") {
      checksum += import::ReadIndexedPng(p).index[0];  // Kubric's palette PNG
    } else if (ext == ".png" || ext == ".tiff") {
      const cv::Mat m = cv::imread(p.string(), cv::IMREAD_UNCHANGED);
      checksum += m.empty() ? 0 : m.data[0];
    } else if (ext == ".npy") {
      checksum += ReadNpy(p).data.size();
    } else if (ext == ".exr") {
      checksum += exr::ReadFlatExr(p, {"R"}).Get("R").floats[0];
    } else if (ext == ".json") {
      checksum += nlohmann::json::parse(ReadFile(p)).size();
    }
  }
  return checksum;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app("frames/s of lsds import on synthesized sources");
  int frames = 300;
  std::string size = "160x120";
  std::string format = "all";
  app.add_option("--frames", frames, "frames in the source");
  app.add_option("--size", size, "WIDTHxHEIGHT");
  app.add_option("--format",
                 format,
                 "ue-mrq, kubric, replicator, replicator-products, replicator-noseg, solo or all");
  CLI11_PARSE(app, argc, argv);
  int width = 0, height = 0;
  if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2) return 2;

  const fs::path root =
      fs::temp_directory_path() / ("lsds_bench_import_" + size + "_" + std::to_string(frames));
  synth::Spec spec = synth::CircleSpec(frames, width, height);
  spec.samples_per_axis = 1;
  for (const std::string f :
       {"ue-mrq", "kubric", "replicator", "replicator-products", "replicator-noseg", "solo"}) {
    if (format != "all" && format != f) continue;
    const std::string importer = f.rfind("replicator", 0) == 0 ? "replicator" : f;
    const fs::path source = root / f;
    const fs::path done = root / (f + ".done");
    import::ImportOptions options;
    if (!fs::exists(done)) {
      std::cout << "synthesizing " << frames << " " << f << " frames into " << source << " ...\n";
      fs::remove_all(source);
      if (f == "ue-mrq") {
        testing::WriteMrqFixture(source, spec, {});
      } else if (f == "kubric") {
        synth::Spec perspective = spec;
        perspective.depth_kind = DepthKind::kPerspective;
        testing::WriteKubricFixture(source, perspective);
      } else if (f == "replicator") {
        testing::WriteReplicatorFixture(source, spec);
      } else if (f == "replicator-products") {
        // Two products of half the frames each: the same number of frames to import.
        synth::Spec half = spec;
        half.cam_from_world.resize(static_cast<size_t>(frames / 2));
        testing::ReplicatorLayout layout;
        layout.products = {"Replicator", "Replicator_01"};
        testing::WriteReplicatorFixture(source, half, layout);
      } else if (f == "replicator-noseg") {
        testing::ReplicatorLayout layout;
        layout.instance_segmentation = false;
        testing::WriteReplicatorFixture(source, spec, layout);
      } else {
        testing::WriteSoloFixture(source, spec, frames);
      }
      WriteFileAtomic(done, "");
    }
    if (importer == "replicator") options.up_axis = "y";

    auto start = std::chrono::steady_clock::now();
    const double checksum =
        f == "ue-mrq" ? MrqFloor(source) : FileFloor(source, f == "replicator-noseg");
    const double floor = Seconds(start);

    const fs::path out = root / (f + "_collection");
    start = std::chrono::steady_clock::now();
    const import::ImportResult result =
        import::ImportCollection(importer, source, out, options, /*force=*/true);
    const double seconds = Seconds(start);
    std::printf("import %s: %lld frames %dx%d, %lld object entries\n",
                f.c_str(),
                static_cast<long long>(result.frames),
                width,
                height,
                static_cast<long long>(result.objects));
    const double imported = static_cast<double>(result.frames);
    std::printf("  floor (decode the source files): %8.1f frames/s\n", imported / floor);
    std::printf(
        "  lsds import:                     %8.1f frames/s  (%.2fx the "
        "floor)\n",
        imported / seconds,
        seconds / floor);
    std::printf("  peak memory so far: %ld MB%s\n", PeakRssMb(), checksum == 12345.678 ? " " : "");
    fs::remove_all(out);
  }
  return 0;
}
