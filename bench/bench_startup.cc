// Benchmark of start-up (bench/README.md, "Start-up"): how long a short lsds command takes as a
// whole process, how much memory it peaks at and how many shared libraries it loads. A CI gate
// that calls lsds once per collection or shard pays this each time (issue 48: <= 20 ms and
// <= 20 MiB for `lsds --version`, <= 30 ms for `lsds info` of a small collection).
//
// Each command runs --runs times (20) as a child process; the table gives the median wall time,
// the median CPU time (user + system: what the process itself costs, less sensitive than wall
// time to other work on the machine), the median peak RSS, and the shared objects the dynamic
// loader mapped (one more run with LD_DEBUG=files: the libraries the binary links and the
// plug-ins the command opened, without the binary itself). The small collection is
// `lsds synth`'s default: 4 frames of 640x480.
//
//   bench_startup [--runs N] [--lsds PATH] [--work DIR]
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/child_process.h"
#include "tests/build_paths.h"

namespace fs = std::filesystem;
using lsds::bench::ChildRun;
using lsds::bench::RunChild;

namespace {

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The shared objects the loader mapped for one run of `args`: its LD_DEBUG=files log names each
// with "generating link map" (the executable and the vDSO are not among them).
int LoadedObjects(const std::vector<std::string>& args, const fs::path& work) {
  const fs::path log = work / "ld_debug";
  RunChild(args, {"LD_DEBUG=files", "LD_DEBUG_OUTPUT=" + log.string()});
  int count = 0;
  for (const auto& entry : fs::directory_iterator(work)) {
    if (entry.path().filename().string().rfind("ld_debug.", 0) != 0) continue;
    std::ifstream in(entry.path());
    for (std::string line; std::getline(in, line);)
      if (line.find("generating link map") != std::string::npos) ++count;
    fs::remove(entry.path());
  }
  return count;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 20;
  std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  fs::path work = fs::temp_directory_path() / "lsds_bench_startup";
  CLI::App app{
      "bench_startup: wall time, CPU time, peak memory and shared libraries of short lsds "
      "commands"};
  app.add_option("--runs", runs, "runs per command (the median is printed)")
      ->check(CLI::PositiveNumber);
  app.add_option("--lsds", lsds, "the lsds binary");
  app.add_option("--work", work, "scratch folder (removed at the end)");
  CLI11_PARSE(app, argc, argv);

  fs::remove_all(work);
  fs::create_directories(work);
  const std::string small = (work / "small").string();
  if (RunChild({lsds, "synth", "-q", small}).exit_code != 0) {
    std::fprintf(stderr, "bench_startup: `%s synth %s` failed\n", lsds.c_str(), small.c_str());
    return 2;
  }
  const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
      {"lsds --version", {lsds, "--version"}},
      {"lsds info (4 frames)", {lsds, "info", small}},
  };
  std::printf("start-up of %s, median of %d runs\n\n", lsds.c_str(), runs);
  std::printf("| command | wall ms | CPU ms | peak MiB | shared libraries loaded |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const auto& [name, args] : commands) {
    std::vector<double> wall, cpu, peak;
    for (int i = 0; i < runs; ++i) {
      const ChildRun run = RunChild(args);
      if (run.exit_code != 0) {
        std::fprintf(stderr, "bench_startup: %s exited with %d\n", name.c_str(), run.exit_code);
        return 2;
      }
      wall.push_back(1e3 * run.seconds);
      cpu.push_back(1e3 * run.cpu_seconds);
      peak.push_back(run.peak_mib);
    }
    std::printf("| `%s` | %.1f | %.1f | %.1f | %d |\n",
                name.c_str(),
                Median(wall),
                Median(cpu),
                Median(peak),
                LoadedObjects(args, work));
  }
  fs::remove_all(work);
  return 0;
}
