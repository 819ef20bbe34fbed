// lsds plan SCENE [CAPTURE] [-o plan.json] [--seed N] [--frames A:B]
// [--emit-json] [--force]
#include <iostream>

#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "generator/plan_source.h"
#include "generator/requirement_report.h"
#include "libs/util/atomic_file.h"
#include "libs/util/input_file.h"
#include "libs/util/output_guard.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

int RunPlan(int argc, char** argv) {
  CLI::App app(
      "Expand an LSCENE scene (and an LCAP capture) into the frame plan the "
      "renderer consumes.",
      "lsds plan");
  std::string scene, capture, output;
  uint64_t seed = 0;
  bool emit_json = false;
  app.add_option("SCENE", scene, "LSCENE file (text notation or .json)")->required();
  app.add_option(
      "CAPTURE", capture, "LCAP file (text notation or .json); default: one nadir frame");
  app.add_option("-o,--output", output, "write the plan (or the JSON form) here instead of stdout");
  app.add_option("--seed", seed, "random seed (same files + seed = same plan, byte for byte)");
  app.add_flag("--emit-json",
               emit_json,
               "print the JSON form of the scene (and capture) instead of the plan");
  CommonFlags common;
  AddCommonFlags(app, &common, "overwrite the output file");
  return RunCommand(app, common, argc, argv, [&] {
    // What the inputs are first: `lsds plan DIR` is told DIR is a folder.
    RequireRegularFile(scene, "scene file");
    if (!capture.empty()) RequireRegularFile(capture, "capture file");
    OutputGuard guard("lsds plan");
    guard.AddInput(scene, "scene file");
    guard.AddInput(capture, "capture file");
    guard.CheckOutput(output, "-o");
    if (!output.empty()) RefuseToOverwrite(output, common.force, "plan");
    std::string text;
    if (emit_json) {
      const SourceFile s = LoadSource(scene);
      for (const std::string& w : s.warnings) std::cerr << "lsds plan: warning: " << w << "\n";
      if (capture.empty()) {
        text = SourceToJson(s).dump(2);
      } else {
        const SourceFile c = LoadSource(capture);
        for (const std::string& w : c.warnings) std::cerr << "lsds plan: warning: " << w << "\n";
        text =
            nlohmann::ordered_json{{"scene", SourceToJson(s)}, {"capture", SourceToJson(c)}}.dump(
                2);
      }
    } else {
      const Plan plan = gen::PlanFromScene(scene, capture, seed, FramesFlag(common));
      for (const std::string& w : plan.warnings) std::cerr << "lsds plan: warning: " << w << "\n";
      text = PlanToJson(plan).dump(1);
      if (!common.quiet) std::cerr << gen::FormatPlannedRequirements(plan);
    }
    if (output.empty()) {
      std::cout << text << "\n";
    } else {
      WriteFileAtomic(output, text + "\n");
    }
    return 0;
  });
}

}  // namespace lsds
