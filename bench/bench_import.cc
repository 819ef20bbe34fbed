// bench_import: frames/s of `lsds import ue-mrq` on a synthesized Movie Render
// Queue folder (tests/import/mrq_fixture.h: multipart EXRs with the final
// image, World Depth and Cryptomatte, plus the sidecar), next to the floor
// (opening each EXR and decoding the channels the importer reads), the ratio,
// and the peak memory (flat in the number of frames: one frame at a time).
//
//   bench_import                              300 frames at 160x120 (make
//   bench) bench_import --frames 300 --size 640x480
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>

#include "libs/importers/import_collection.h"
#include "libs/importers/source_exr.h"
#include "libs/synth/synthetic_collection.h"
#include "tests/import/mrq_fixture.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {
double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}
long PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app("frames/s of lsds import ue-mrq on a synthesized source");
  int frames = 300;
  std::string size = "160x120";
  app.add_option("--frames", frames, "frames in the source");
  app.add_option("--size", size, "WIDTHxHEIGHT");
  CLI11_PARSE(app, argc, argv);
  int width = 0, height = 0;
  if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2) return 2;

  const fs::path root =
      fs::temp_directory_path() /
      ("lsds_bench_import_" + size + "_" + std::to_string(frames));
  const fs::path source = root / "mrq";
  synth::Spec spec = synth::CircleSpec(frames, width, height);
  spec.samples_per_axis = 1;
  if (!fs::exists(source / "lsds_objects.json")) {
    std::cout << "synthesizing " << frames << " MRQ frames into " << source
              << " ...\n";
    fs::remove_all(source);
    testing::WriteMrqFixture(source, spec, {});
  }

  // Floor: open every EXR and decode the channels the importer reads.
  auto start = std::chrono::steady_clock::now();
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
  const double floor = Seconds(start);

  const fs::path out = root / "collection";
  start = std::chrono::steady_clock::now();
  const import::ImportResult result =
      import::ImportCollection("ue-mrq", source, out, {}, /*force=*/true);
  const double seconds = Seconds(start);
  std::printf("import ue-mrq: %lld frames %dx%d, %lld object entries\n",
              static_cast<long long>(result.frames),
              width,
              height,
              static_cast<long long>(result.objects));
  std::printf("  floor (decode source channels): %8.1f frames/s\n",
              frames / floor);
  std::printf(
      "  lsds import:                    %8.1f frames/s  (%.2fx the "
      "floor)\n",
      frames / seconds,
      seconds / floor);
  std::printf("  peak memory: %ld MB%s\n",
              PeakRssMb(),
              checksum == 12345.678 ? " " : "");
  fs::remove_all(out);
  return 0;
}
