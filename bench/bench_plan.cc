// Benchmark of planning scenes of many objects (docs/languages.md, "Position: Algorithm 1"): N
// boxes placed ON a terrain whose area grows with N (the same density at every size: about 2 % of
// the ground covered, overlaps moved), planned without a capture. Prints, per size, the plan time,
// the time per object, the growth exponent against the size before (1 = linear; n log n shows
// as a little over 1), and the process's peak memory. Then a capture of F frames over a small
// scene (a lawnmower grid, a material change of 20 objects on every frame, a moving object kept on
// the terrain): the capture's plan time and the time per frame (the LCAP evaluator's cost).
//
//   bench_plan [--sizes 1000,10000,100000] (add 1000000 for the parser's maximum)
//              [--frames 10000] (0: no capture run)
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "generator/lang/planner.h"
#include "generator/lang/source.h"

using Clock = std::chrono::steady_clock;

namespace {

// A square terrain holding n boxes of 1 x 1 m at 2 % cover.
std::string Scene(int64_t n) {
  const double side = std::ceil(std::sqrt(static_cast<double>(n) / 0.02));
  const std::string half = std::to_string(0.5 * side - 1);
  return "LSCENE = ONE(W) MANY(B, " + std::to_string(n) +
         ")\n"
         "W = terrain{size:[" +
         std::to_string(side) + "," + std::to_string(side) +
         "]}\n"
         "B = object{class:cube,extent:[1,1,1],rotation:[0,0,[0,360]],"
         "position:{ON:W,within:[[-" +
         half + ",-" + half + ",-9],[" + half + "," + half + ",9]]},retries:20}\n";
}

// A capture of `frames` frames (a square grid of nadir poses, rounded up to whole rows).
std::string Capture(int64_t frames) {
  const int64_t side = static_cast<int64_t>(std::ceil(std::sqrt(static_cast<double>(frames))));
  const std::string n = std::to_string(side);
  return "LCAP = ONE(CO) ONE(G) ONE(P) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[640,480],fps:10}}\n"
         "G = path{grid:{x:[-40,40," +
         n + "],y:[-40,40," + n +
         "],altitude:30}}\n"
         "P = path{waypoints:{points:[[-40,0,0.5],[40,0,0.5]],speed:2}}\n"
         "CL = collection{CO:{move:[G]},B:{during:G,material:{rust:0.5,plastic:0.5}},"
         "M:{move:[P:100]}}\n";
}

const char* kCaptureScene =
    "LSCENE = ONE(W) MANY(B, 20) ONE(M)\n"
    "W = terrain{size:[100,100]}\n"
    "B = object{class:cube,extent:[1,1,1],position:{ON:W,within:[[-40,-40,-9],[40,40,9]]}}\n"
    "M = object{class:car,extent:[4,2,1.5],position:{ON:W},overlap:true}\n";

double PeakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"plan time and memory against the number of objects"};
  std::vector<int64_t> sizes = {1000, 10000, 100000};
  int64_t frames = 10000;
  app.add_option("--sizes", sizes, "object counts")->delimiter(',');
  app.add_option("--frames", frames, "frames of the capture run (0: none)");
  CLI11_PARSE(app, argc, argv);

  std::printf("%10s %10s %10s %14s %8s %10s\n",
              "objects",
              "placed",
              "plan_s",
              "us_per_object",
              "growth",
              "peak_MiB");
  double previous_s = 0;
  int64_t previous_n = 0;
  for (const int64_t n : sizes) {
    const lsds::SourceFile scene = lsds::ParseSource(Scene(n), "bench.lscene", false);
    const auto start = Clock::now();
    const lsds::Plan plan = lsds::MakePlanFromSources(scene, nullptr, 1);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const double growth = previous_n > 0 ? std::log(seconds / previous_s) /
                                               std::log(static_cast<double>(n) / previous_n)
                                         : 0.0;
    std::printf("%10lld %10zu %10.3f %14.2f %8.2f %10.1f\n",
                static_cast<long long>(n),
                plan.objects.size(),
                seconds,
                1e6 * seconds / static_cast<double>(n),
                growth,
                PeakMiB());
    std::fflush(stdout);
    previous_s = seconds;
    previous_n = n;
  }
  if (frames <= 0) return 0;
  const lsds::SourceFile scene = lsds::ParseSource(kCaptureScene, "bench.lscene", false);
  const lsds::SourceFile capture = lsds::ParseSource(Capture(frames), "bench.lcap", false);
  const auto start = Clock::now();
  const lsds::Plan plan = lsds::MakePlanFromSources(scene, &capture, 1);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("\n%10s %10s %14s %10s\n", "frames", "plan_s", "us_per_frame", "peak_MiB");
  std::printf("%10zu %10.3f %14.2f %10.1f\n",
              plan.frames.size(),
              seconds,
              1e6 * seconds / static_cast<double>(plan.frames.size()),
              PeakMiB());
  return 0;
}
