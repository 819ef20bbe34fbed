// perturb-metadata throughput: a collection of N frames (default 10,000;
// collection.json and metadata.json only, with three targets per frame) is
// perturbed with and without --report. The floor: 10,000 frames in
// under a second.
//   perturb_metadata_bench [--frames N] [--keep DIR]
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <unistd.h>

#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "perturb/perturb_collection.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

void WriteCollection(const fs::path& root, int frames) {
  fs::create_directories(root);
  CollectionHeader header;
  header.provenance.generator = "perturb_metadata_bench";
  header.provenance.generator_version = "0";
  header.classes = {{1, "box"}};
  header.layers = {StandardLayer("rgb")};
  header.metadata = {{kMetadataFile, false, "truth"}};
  header.frame_count = frames;
  MetadataHeader metadata_header;
  metadata_header.frame_count = frames;
  CollectionWriter collection(root, header);
  MetadataWriter metadata(root / kMetadataFile, metadata_header);
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(1024, 768, 60);
  for (int k = 0; k < frames; ++k) {
    Frame frame;
    frame.index = k;
    frame.time = 0.1 * k;
    frame.sequence = "S1";
    frame.camera.intrinsics = camera;
    const Rigid3d cam_from_world = CamFromEnu({0.5 * k, 0.0, 60.0}, Attitude{0.0, -60.0, 90.0});
    frame.camera.cam_from_world_rotation = cam_from_world.rotation.toRotationMatrix();
    frame.camera.cam_from_world_translation = cam_from_world.translation;
    frame.files["rgb"] = "rgb/" + std::to_string(k) + ".exr";
    for (int o = 0; o < 3; ++o) {
      ObjectTruth object;
      object.instance_id = o + 1;
      object.class_id = 1;
      object.obb.emplace();
      object.obb->center = {0.5 * k + 30.0 + 5 * o, -5.0 + 5 * o, 1.0};
      object.obb->half_extents = {2.0, 1.0, 1.0};
      object.in_frame = 1.0;
      object.visibility = 1.0;
      object.visible_pixels = 100;
      object.bbox = Box2d{100, 100, 120, 120};
      frame.objects.push_back(object);
    }
    collection.Append(frame);
    metadata.Append(TruthMetadata(frame, header.conventions.world));
  }
  collection.Commit();
  metadata.Commit();
}

double Seconds(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 2000;
  std::string keep;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--frames") == 0 && i + 1 < argc) {
      frames = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--keep") == 0 && i + 1 < argc) {
      keep = argv[++i];
    } else {
      const bool help = std::strcmp(argv[i], "--help") == 0;
      (help ? std::cout : std::cerr)
          << "usage: bench_perturb_metadata [--frames N (default 2000; the "
             "issue's size is 10000)] "
             "[--keep DIR]\n";
      return help ? 0 : 2;
    }
  }
  const fs::path root = keep.empty() ? fs::temp_directory_path() /
                                           ("lsds-perturb-bench-" + std::to_string(::getpid()))
                                     : fs::path(keep);
  fs::remove_all(root);
  auto start = std::chrono::steady_clock::now();
  WriteCollection(root, frames);
  std::cout << "built " << frames << " frames in " << Seconds(start) << " s ("
            << fs::file_size(root / "collection.json") / 1e6 << " MB collection.json, "
            << fs::file_size(root / "metadata.json") / 1e6 << " MB metadata.json)\n";

  {
    std::ifstream load("/proc/loadavg");
    std::string one_minute;
    if (load >> one_minute) std::cout << "load average (1 min): " << one_minute << "\n";
  }
  noise::PerturbOptions options;
  options.collection = root;
  options.progress = false;
  options.force = true;
  options.spec.seed = 1;
  options.spec.sigma = {1.0, 1.0, 2.0, 0.1, 0.1, 0.3, 0.001, 0.05};
  const double floor_s = 1.0 * frames / 10000.0;  // 10,000 frames per second
  for (const char* model : {"gaussian", "gauss-markov"}) {
    for (bool report : {false, true}) {
      options.spec.model = noise::ParseNoiseModel(model);
      options.spec.tau = options.spec.model == noise::NoiseModel::kGaussMarkov ? 5.0 : 0.0;
      options.report = report;
      start = std::chrono::steady_clock::now();
      const std::clock_t cpu_start = std::clock();
      noise::PerturbCollection(options);
      const double seconds = Seconds(start);
      const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
      std::cout << "perturb-metadata " << model << (report ? " --report" : "") << ": " << frames
                << " frames in " << seconds << " s wall (" << cpu << " s CPU), " << frames / seconds
                << " frames/s, ratio to the floor (1 s per 10,000 frames): " << seconds / floor_s
                << (seconds <= floor_s ? " (ok)"
                    : cpu <= floor_s   ? " (slower on the wall clock only: the machine is loaded)"
                                       : " (SLOWER THAN THE FLOOR)")
                << "\n";
    }
  }
  if (keep.empty()) fs::remove_all(root);
  return 0;
}
