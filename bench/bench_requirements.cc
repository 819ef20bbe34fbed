// Benchmark of LCAP requirements and quotas (docs/languages.md, "Requirements
// and quotas"): the planning overhead of the estimates and redraws, as a ratio
// to the render time of the same frames, and the acceptance rate (draws kept /
// draws estimated). The scene is a target half under a plate among clutter,
// seen from random nadir poses; the demands are 40-60 % occlusion, and (second
// run) a quota of four equal visibility bins. The last two runs are the same
// quotas on the off-nadir angle and the target's class (a class swap) drawn by
// rejection and by importance sampling (the bin drawn at once): the
// acceptance rate before and after.
//
//   bench_requirements [--frames N] [--size WxH] [--spp S]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "generator/estimate.h"
#include "generator/generate.h"
#include "generator/lang/planner.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace lsds;

namespace {

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

const char* kScene =
    "LSCENE = ONE(W) ONE(T) ONE(PLATE) MANY(CLUTTER, 40)\n"
    "W = terrain{size:[80,80],height:{perlin:{amplitude:0.5}}}\n"
    "T = object{class:cube,extent:[2,2,1],position:{ON:W,within:[[-1,-1,-9],[1,1,9]]}}\n"
    "PLATE = object{class:cube,extent:[3,1.5,0.1],target:false,"
    "position:{within:[[-1.5,0,3],[1.5,1.5,3.1]]}}\n"
    "CLUTTER = object{class:{rock:0.5,barrel:0.5},target:false,"
    "position:{ON:W,within:[[-35,-35,-9],[35,35,9]]},on_overlap:delete}\n";

std::string Capture(int frames, int w, int h, const std::string& demand) {
  // The sampling runs draw an off-nadir angle and the target's class per frame.
  const bool sampling = demand.find("sampling") != std::string::npos;
  return std::string(demand.empty() ? "LCAP = ONE(CO) ONE(R)\n"
                                    : "LCAP = ONE(CO) ONE(R) ONE(REQ) ONE(CL)\n") +
         "CO = camera{csettings:{fov:60,res:[" + std::to_string(w) + "," + std::to_string(h) +
         "]},targets:[T]}\n"
         "R = path{random:{count:" +
         std::to_string(frames) +
         ",x:[-12,12],y:[-12,12],altitude:30,off_nadir:" + (sampling ? "[0,40]" : "0") +
         ",yaw:0}}\n"
         "CL = collection{CO:{move:[R]}" +
         (sampling ? ",T:{during:R,class:{cube:1,barrel:1,tire:1,rock:1}}" : "") + "}\n" + demand;
}

void Run(const fs::path& dir,
         const std::string& label,
         const std::string& demand,
         int frames,
         int w,
         int h,
         int spp) {
  std::ofstream(dir / "s.lscene") << kScene;
  // The same frames' planning without any demand (no estimator at all).
  std::ofstream(dir / "free.lcap") << Capture(frames, w, h, "");
  std::ofstream(dir / "c.lcap") << Capture(frames, w, h, demand);
  const Clock::time_point f0 = Clock::now();
  MakePlan(dir / "s.lscene", dir / "free.lcap", 1, {}, gen::MakeFrameEstimatorFactory());
  const double free_s = Since(f0);
  const gen::EstimateStats before = gen::GetEstimateStats();
  const Clock::time_point p0 = Clock::now();
  const Plan plan =
      MakePlan(dir / "s.lscene", dir / "c.lcap", 1, {}, gen::MakeFrameEstimatorFactory());
  const double plan_s = Since(p0);
  const gen::EstimateStats after = gen::GetEstimateStats();
  int64_t attempts = 0, met = 0;
  for (const PlannedFrame& f : plan.frames) {
    attempts += f.requirements->value("attempts", 1);
    met += f.requirements->value("met", false);
  }
  gen::GenerateOptions options;
  options.output = dir / ("out-" + label);
  options.force = true;
  options.progress = false;
  options.spp = spp;
  const gen::GenerateSummary summary = gen::GenerateCollection(plan, options);
  const double overhead = plan_s - free_s;
  std::printf(
      "%-10s %4d frames %dx%d spp %d: planning %.3f s (without the demand %.3f s), %lld estimates "
      "(%.3f s, %.2f Mrays), acceptance %.3f (%lld draws kept / %lld estimated), met by estimate "
      "%lld/%d, render %.3f s (total with writing %.3f s); overhead / render = %.3f, / total = "
      "%.3f\n",
      label.c_str(),
      frames,
      w,
      h,
      spp,
      plan_s,
      free_s,
      static_cast<long long>(after.frames - before.frames),
      after.seconds - before.seconds,
      (after.rays - before.rays) / 1e6,
      static_cast<double>(frames) / attempts,
      static_cast<long long>(frames),
      static_cast<long long>(attempts),
      static_cast<long long>(met),
      frames,
      summary.render_seconds,
      summary.total_seconds,
      overhead / summary.render_seconds,
      overhead / summary.total_seconds);
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 20, w = 640, h = 480, spp = 4;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--size")) std::sscanf(argv[i + 1], "%dx%d", &w, &h);
    if (!std::strcmp(argv[i], "--spp")) spp = std::atoi(argv[i + 1]);
  }
  const fs::path dir = fs::temp_directory_path() / "lsds-bench-requirements";
  fs::create_directories(dir);
  Run(dir,
      "occlusion",
      "REQ = require{target:T,occlusion:[0.4,0.6],budget:200}\n",
      frames,
      w,
      h,
      spp);
  Run(dir,
      "quota",
      "REQ = quota{target:T,quantity:visibility,bins:[0,0.25,0.5,0.75,1.0001],budget:200}\n",
      frames,
      w,
      h,
      spp);
  // Off-nadir bins of 5 degrees out of 0-40 and a class out of four: about
  // 1/8 * 1/4 of the unconstrained draws hit a frame's two bins.
  for (const std::string sampling : {"rejection", "importance"})
    Run(dir,
        sampling,
        "REQ = quota{quantity:off_nadir,bins:[0,5,10,15,20,25,30,35,40],sampling:" + sampling +
            ",budget:400}\nQ2 = quota{target:T,quantity:class,classes:[cube,barrel,tire,rock],"
            "sampling:" +
            sampling + "}\n",
        frames,
        w,
        h,
        spp);
  fs::remove_all(dir);
  return 0;
}
