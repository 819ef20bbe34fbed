// bench_validate: `lsds validate` throughput next to its floor, and its peak
// memory as frames grow.
//
//   bench_validate [--frames 200] [--size 1024x1024] [--samples-per-axis 1]
//   [--jobs 0]
//                  [--rss-frames 100,400] [--rss-size 256x256] [--dir
//                  /tmp/lsds_bench_validate]
//
// Floor: reading and decoding the same EXR files (every layer of every frame,
// once, with the same parallelism) and nothing else. Peak RSS is measured in a
// fresh process per collection size, so each figure is that run's own
// high-water mark.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include <tbb/parallel_for.h>

#include "libs/collection/bundle_layout.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"
#include "synth/synthetic_collection.h"
#include "validators/report_writers.h"
#include "validators/validate.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

// CPU seconds of this process (all threads): robust to other load on a shared
// machine.
double CpuNow() {
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Rendering a 1024x1024 frame analytically takes seconds, so `unique` frames (a
// circle flight) are rendered once and the collection is made of copies: frame
// k is a copy of unique frame k % unique, each cycle its own sequence (motion
// is checked within a sequence only). Every file is a real copy, so the I/O is
// that of a collection of `frames` distinct files.
void Generate(const fs::path& dir,
              int frames,
              int width,
              int height,
              int samples_per_axis,
              int unique,
              BundleLayout layout) {
  if (fs::exists(dir / "collection.json")) {
    const CollectionReader reader(dir);
    const LayerInfo* bundle = reader.header().FindLayerBySemantic("bundle");
    bool same = static_cast<int>(reader.frames_in_file()) == frames && bundle != nullptr &&
                bundle->layout == layout;
    reader.ForEachFrame([&](const Frame& f) {
      same = same && f.camera.intrinsics.width == width && f.camera.intrinsics.height == height;
    });
    if (same) return;  // reuse a collection of the right shape
  }
  fs::remove_all(dir);
  unique = std::max(1, std::min(unique, frames));
  synth::Spec spec = synth::CircleSpec(unique, width, height);
  spec.samples_per_axis = samples_per_axis;
  spec.bundle_layout = layout;
  const double start = Now();
  const fs::path source = dir / "unique";
  synth::WriteCollection(source, spec);
  const CollectionReader reader(source);
  std::vector<Frame> rendered;
  reader.ForEachFrame([&](const Frame& f) { rendered.push_back(f); });
  CollectionHeader header = reader.header();
  header.frame_count = frames;
  CollectionWriter collection(dir, header);
  MetadataHeader metadata_header;
  metadata_header.frame_count = frames;
  MetadataWriter metadata(dir / kMetadataFile, metadata_header);
  for (int k = 0; k < frames; ++k) {
    Frame frame = rendered[k % unique];
    frame.index = k;
    frame.time = 0.1 * k;
    frame.sequence = "S" + std::to_string(k / unique);
    for (auto& [layer, file] : frame.files) {
      const std::string copy = layer + "/" + FrameStem(k) + ".exr";
      fs::create_directories(dir / layer);
      fs::copy_file(source / file, dir / copy);
      file = copy;
    }
    collection.Append(frame);
    metadata.Append(TruthMetadata(frame, header.conventions.world));
  }
  metadata.Commit();
  collection.Commit();
  fs::remove_all(source);
  std::printf("  generated %d frames at %dx%d (%d rendered, copied) in %.1f s\n",
              frames,
              width,
              height,
              unique,
              Now() - start);
}

struct Pass {
  double seconds = 0;
  double cpu_seconds = 0;
  int64_t bytes = 0;
  int64_t files = 0;
};

// The floor: decode every layer file of every frame, batch by batch as validate
// does, nothing else.
Pass DecodeOnly(const fs::path& dir, size_t batch_size) {
  const double start = Now(), cpu_start = CpuNow();
  const CollectionReader reader(dir);
  Pass pass;
  std::vector<Frame> batch;
  std::atomic<int64_t> bytes{0}, files{0};
  auto flush = [&] {
    tbb::parallel_for(size_t{0}, batch.size(), [&](size_t i) {
      for (const LayerInfo& layer : reader.header().layers) {
        const fs::path path = reader.LayerPath(batch[i], layer.name);
        if (layer.deep) {
          ReadBundleExr(path);  // either bundle layout
        } else {
          exr::ReadFlatExr(path);
        }
        bytes += static_cast<int64_t>(fs::file_size(path));
        ++files;
      }
    });
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& frame) {
    batch.push_back(frame);
    if (batch.size() == batch_size) flush();
  });
  flush();
  pass.seconds = Now() - start;
  pass.cpu_seconds = CpuNow() - cpu_start;
  pass.bytes = bytes;
  pass.files = files;
  return pass;
}

Pass Validate(const fs::path& dir,
              const validate::ValidateOptions& options,
              validate::Report* out = nullptr) {
  const double start = Now(), cpu_start = CpuNow();
  validate::Report report = validate::ValidateCollection(dir, options);
  Pass pass;
  pass.seconds = Now() - start;
  pass.cpu_seconds = CpuNow() - cpu_start;
  pass.bytes = report.bytes_decoded;
  pass.files = report.files_decoded;
  if (report.Fails(validate::Severity::kWarning)) {
    std::fprintf(
        stderr, "%s", validate::ReportToText(report, validate::Severity::kWarning).c_str());
  }
  if (out) *out = std::move(report);
  return pass;
}

// Peak RSS (MB) of a child process that runs `fn`.
// Peak RSS (MB) of a fresh process (this binary re-executed with `mode`), so
// that nothing of this process's own heap is inherited into the figure.
double PeakRssMb(const std::string& mode, const fs::path& dir, int jobs) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string jobs_text = std::to_string(jobs);
    execl("/proc/self/exe",
          "bench_validate",
          mode.c_str(),
          dir.c_str(),
          jobs_text.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return -1;
  return usage.ru_maxrss / 1024.0;
}

bool ParseSize(const std::string& text, int* w, int* h) {
  return std::sscanf(text.c_str(), "%dx%d", w, h) == 2;
}

}  // namespace

int main(int argc, char** argv) {
  // Small defaults for `make bench`; the issue-sized run is
  //   bench_validate --frames 200 --size 1024x1024 --rss-frames 100,400
  //   --rss-size 256x256
  int frames = 24, width = 256, height = 256, samples = 1, jobs = 0, unique = 8, rss_w = 128,
      rss_h = 128;
  BundleLayout layout = BundleLayout::kResidual;  // what the generator writes
  std::vector<int> rss_frames = {25, 100};
  fs::path dir = fs::temp_directory_path() / "lsds_bench_validate";
  if (argc == 4 && (std::strcmp(argv[1], "--child-validate") == 0 ||
                    std::strcmp(argv[1], "--child-decode") == 0)) {
    const int child_jobs = std::atoi(argv[3]);
    const ThreadLimit child_threads(child_jobs);
    validate::ValidateOptions child_options;
    child_options.jobs = child_jobs;
    if (std::strcmp(argv[1], "--child-validate") == 0) {
      Validate(argv[2], child_options);
    } else {
      DecodeOnly(argv[2], child_options.batch_size);
    }
    return 0;
  }
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : "";
    if (arg == "--frames") {
      frames = std::atoi(value), ++i;
    } else if (arg == "--size") {
      if (!ParseSize(value, &width, &height)) return 2;
      ++i;
    } else if (arg == "--samples-per-axis") {
      samples = std::atoi(value), ++i;
    } else if (arg == "--unique") {
      unique = std::atoi(value), ++i;
    } else if (arg == "--jobs") {
      jobs = std::atoi(value), ++i;
    } else if (arg == "--rss-frames") {
      rss_frames.clear();
      for (const std::string& n : Split(value, ',')) {
        if (!n.empty()) rss_frames.push_back(std::atoi(n.c_str()));
      }
      ++i;
    } else if (arg == "--rss-size") {
      if (!ParseSize(value, &rss_w, &rss_h)) return 2;
      ++i;
    } else if (arg == "--dir") {
      dir = value, ++i;
    } else if (arg == "--bundle-layout") {
      if (!ParseBundleLayout(value, &layout)) return 2;
      ++i;
    } else {
      std::cerr << "usage: bench_validate [--frames N] [--size WxH] "
                   "[--samples-per-axis N] [--jobs N] [--unique N]\n"
                   "                      [--bundle-layout residual|compact|full]\n"
                   "                      [--rss-frames A,B] [--rss-size WxH] "
                   "[--dir PATH]\n";
      return arg == "--help" ? 0 : 2;
    }
  }
  const ThreadLimit threads(jobs);
  validate::ValidateOptions options;
  options.jobs = jobs;

  std::printf(
      "bench_validate: %d frames at %dx%d, %d bundle sample(s) per pixel, %s bundle layout, %s "
      "threads\n",
      frames,
      width,
      height,
      samples * samples,
      BundleLayoutName(layout),
      jobs > 0 ? std::to_string(jobs).c_str() : "all");
  const fs::path main_dir = dir / ("throughput_" + std::to_string(frames) + "_" +
                                   std::to_string(width) + "x" + std::to_string(height) + "_" +
                                   std::to_string(samples) + "_" + BundleLayoutName(layout));
  if (frames > 0) {  // --frames 0: memory figures only
    Generate(main_dir, frames, width, height, samples, unique, layout);
    DecodeOnly(main_dir,
               options.batch_size);  // warm the page cache for both timed passes
    const Pass floor = DecodeOnly(main_dir, options.batch_size);
    validate::Report report;
    const Pass validation = Validate(main_dir, options, &report);
    const double mb = floor.bytes / 1e6;
    std::printf(
        "  floor (decode every EXR once):   %7.2f s  %7.1f frames/s  %8.1f "
        "MB/s  "
        "(%lld files, %.0f MB)\n",
        floor.seconds,
        frames / floor.seconds,
        mb / floor.seconds,
        static_cast<long long>(floor.files),
        mb);
    std::printf(
        "  lsds validate (all %zu checks): %7.2f s  %7.1f frames/s  %8.1f MB/s "
        " "
        "(%lld files decoded)\n",
        report.checks.size(),
        validation.seconds,
        frames / validation.seconds,
        validation.bytes / 1e6 / validation.seconds,
        static_cast<long long>(validation.files));
    std::printf("  ratio validate / floor: %.3f wall, %.3f CPU (aim <= 1.25)\n",
                validation.seconds / floor.seconds,
                validation.cpu_seconds / floor.cpu_seconds);
    std::printf("  CPU seconds: floor %.2f, validate %.2f (%.1f / %.1f ms per frame)\n",
                floor.cpu_seconds,
                validation.cpu_seconds,
                1e3 * floor.cpu_seconds / frames,
                1e3 * validation.cpu_seconds / frames);
    std::printf("  %s\n", validate::Verdict(report, validate::Severity::kWarning).c_str());
  }

  std::fflush(stdout);
  for (int n : rss_frames) {
    const fs::path rss_dir = dir / ("rss_" + std::to_string(n) + "_" + std::to_string(rss_w) + "x" +
                                    std::to_string(rss_h) + "_" + std::to_string(samples) + "_" +
                                    BundleLayoutName(layout));
    Generate(rss_dir, n, rss_w, rss_h, samples, unique, layout);
    const double floor_rss = PeakRssMb("--child-decode", rss_dir, jobs);
    const double rss = PeakRssMb("--child-validate", rss_dir, jobs);
    std::printf("  peak RSS, %4d frames at %dx%d: validate %7.1f MB, floor %7.1f MB\n",
                n,
                rss_w,
                rss_h,
                rss,
                floor_rss);
  }
  return 0;
}
