// Benchmark of scaling a generate run out (docs/scale-out.md): the same frames rendered
// by one `lsds generate` process and by N shard processes side by side
// (`--shard I/N`, each with cores/N threads), the speedup on this machine, and
// `lsds merge` of the shards next to copying the same bytes (its floor); then
// `lsds validate` of the result in one process vs N `--shard` processes joined
// by `lsds merge-reports`.
//
//   bench_scaleout [--grid 4x3] [--size 256x192] [--spp 1] [--shards 2]
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include "tests/build_paths.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

int Run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string Quote(const fs::path& path) { return "'" + path.string() + "'"; }

// Bytes of every regular file under `root`, and the files' count.
uint64_t TreeBytes(const fs::path& root, int64_t* files) {
  uint64_t bytes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file()) {
      bytes += entry.file_size();
      ++*files;
    }
  return bytes;
}

bool SameTree(const fs::path& a, const fs::path& b) {
  return Run("diff -r " + Quote(a) + " " + Quote(b) + " >/dev/null") == 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lsds generate in N shard processes vs one; lsds merge vs copy"};
  std::string grid = "4x3", size = "256x192";
  int spp = 1, shards = 2;
  app.add_option("--grid", grid, "survey grid, XxY frames (default 4x3)");
  app.add_option("--size", size, "image size WxH (default 256x192)");
  app.add_option("--spp", spp, "samples per pixel (default 1)");
  app.add_option("--shards", shards, "N shard processes (default 2)");
  CLI11_PARSE(app, argc, argv);
  const std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  const fs::path dir =
      fs::temp_directory_path() / ("lsds_bench_scaleout_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  const int threads_per_shard = std::max(1, cores / shards);

  // The capture: the demo survey with the grid and size asked for.
  std::ifstream in(::lsds::testing::SourceDir() + "/examples/demo_survey.lcap");
  std::string capture((std::istreambuf_iterator<char>(in)), {});
  const size_t x = grid.find('x'), w = size.find('x');
  capture = std::regex_replace(capture,
                               std::regex(R"(res:\[512,512\])"),
                               "res:[" + size.substr(0, w) + "," + size.substr(w + 1) + "]");
  capture = std::regex_replace(
      capture, std::regex(R"(x:\[-40,40,6\])"), "x:[-40,40," + grid.substr(0, x) + "]");
  capture = std::regex_replace(
      capture, std::regex(R"(y:\[-25,25,4\])"), "y:[-25,25," + grid.substr(x + 1) + "]");
  std::ofstream(dir / "bench.lcap") << capture;
  const std::string generate = "CI=true " + lsds + " generate " + ::lsds::testing::SourceDir() +
                               "/examples/uav_survey.lscene " + Quote(dir / "bench.lcap") +
                               " -q --seed 1 --spp " + std::to_string(spp);

  std::printf("bench_scaleout: %s frames at %s, spp %d, %d cores, %d shards\n",
              grid.c_str(),
              size.c_str(),
              spp,
              cores,
              shards);
  Clock::time_point t = Clock::now();
  if (Run(generate + " -o " + Quote(dir / "single")) != 0) return 1;
  const double single = Since(t);

  // N processes at once, each with its share of the cores.
  t = Clock::now();
  std::string parallel;
  for (int i = 0; i < shards; ++i)
    parallel += generate + " --threads " + std::to_string(threads_per_shard) + " --shard " +
                std::to_string(i) + "/" + std::to_string(shards) + " -o " +
                Quote(dir / ("shard-" + std::to_string(i))) + " & ";
  if (Run("(" + parallel + "wait)") != 0) return 1;
  const double sharded = Since(t);

  std::string shard_dirs;
  for (int i = 0; i < shards; ++i) shard_dirs += " " + Quote(dir / ("shard-" + std::to_string(i)));
  // The shards were just written: the page cache is warm for the merge and
  // the copy alike.
  int64_t files = 0;
  const uint64_t bytes = TreeBytes(dir / "single", &files);
  t = Clock::now();
  if (Run(lsds + " merge -q" + shard_dirs + " -o " + Quote(dir / "merged")) != 0) return 1;
  const double merge = Since(t);
  // The floor: copying the same files (cp -r of every shard).
  t = Clock::now();
  fs::create_directories(dir / "copied");
  for (int i = 0; i < shards; ++i)
    fs::copy(dir / ("shard-" + std::to_string(i)),
             dir / "copied" / std::to_string(i),
             fs::copy_options::recursive);
  const double copy = Since(t);
  // What any lsds command costs before it starts working (loading the binary
  // and its libraries), part of the merge's time.
  t = Clock::now();
  Run(lsds + " help >/dev/null");
  const double start = Since(t);
  const bool identical = SameTree(dir / "single", dir / "merged");

  std::printf("  one process (%d threads):      %8.2f s\n", cores, single);
  std::printf("  %d shard processes (%d threads each): %8.2f s   speedup %.2fx\n",
              shards,
              threads_per_shard,
              sharded,
              single / sharded);
  std::printf(
      "  merge: %.3f s for %lld files, %.1f MB (%.0f MB/s); copying the "
      "same bytes: %.3f s; ratio merge / copy %.2fx\n",
      merge,
      static_cast<long long>(files),
      bytes / 1e6,
      bytes / 1e6 / merge,
      copy,
      merge / copy);
  std::printf(
      "  (of the merge, %.3f s is starting the lsds process; merge "
      "minus start / copy %.2fx)\n",
      start,
      (merge - start) / copy);
  std::printf("  merged == single run, byte for byte: %s\n", identical ? "yes" : "NO");

  // Validation in shards: one `lsds validate` vs N `--shard I/N` processes at
  // once, then `lsds merge-reports` (which decodes nothing: the floor of the
  // join is starting a process).
  t = Clock::now();
  Run(lsds + " validate --format junit -o " + Quote(dir / "single.xml") + " " +
      Quote(dir / "single") + " 2>/dev/null");
  const double validate_single = Since(t);
  t = Clock::now();
  std::string validate_parallel, parts;
  for (int i = 0; i < shards; ++i) {
    const fs::path part = dir / ("part-" + std::to_string(i) + ".json");
    validate_parallel += lsds + " validate --threads " + std::to_string(threads_per_shard) +
                         " --shard " + std::to_string(i) + "/" + std::to_string(shards) + " -o " +
                         Quote(part) + " " + Quote(dir / "single") + " 2>/dev/null & ";
    parts += " " + Quote(part);
  }
  Run("(" + validate_parallel + "wait)");
  const double validate_sharded = Since(t);
  t = Clock::now();
  Run(lsds + " merge-reports --format junit -o " + Quote(dir / "merged.xml") + parts +
      " 2>/dev/null");
  const double merge_reports = Since(t);
  // Equal but for the measured times.
  auto without_times = [](const fs::path& file) {
    std::ifstream in(file);
    const std::string xml((std::istreambuf_iterator<char>(in)), {});
    return std::regex_replace(xml, std::regex(R"( time="[^"]*")"), "");
  };
  const bool same_report = without_times(dir / "single.xml") == without_times(dir / "merged.xml");
  std::printf("  validate, one process:         %8.2f s\n", validate_single);
  std::printf(
      "  validate, %d shard processes:   %8.2f s   speedup %.2fx; "
      "merge-reports %.3f s (%.2fx the process start)\n",
      shards,
      validate_sharded,
      validate_single / validate_sharded,
      merge_reports,
      merge_reports / start);
  std::printf("  merged report == single run's (times apart): %s\n", same_report ? "yes" : "NO");
  fs::remove_all(dir);
  return identical && same_report ? 0 : 1;
}
