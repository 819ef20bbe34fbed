// lsds export-scene SCENE [CAPTURE] -o DIR [--frames A:B] [--seed N] [--force]:
// each planned frame's scene as glTF 2.0 and JSON (docs/export.md). The work
// lives in generator/scene_export/scene_export.h; this file parses flags.
#include <iostream>

#include "generator/plan_source.h"
#include "generator/scene_export/scene_export.h"
#include "libs/util/input_file.h"
#include "libs/util/output_guard.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

int RunExportScene(int argc, char** argv) {
  CLI::App app(
      "Write each planned frame's scene (world-space triangles as binary glTF 2.0, camera, sun, "
      "sky, exposure and ids as JSON) for renderers other than lsds's own",
      "lsds export-scene");
  std::string scene, capture;
  uint64_t seed = 0;
  gen::SceneExportOptions options;
  app.add_option("SCENE", scene, "LSCENE file (text notation or .json)")->required();
  app.add_option(
      "CAPTURE", capture, "LCAP file (text notation or .json); default: one nadir frame");
  app.add_option("-o,--output", options.output, "output folder")->required();
  app.add_option("--seed", seed, "random seed of the plan (default 0), as for lsds generate");
  CommonFlags common;
  AddCommonFlags(app, &common, "replace an existing export folder");
  return RunCommand(app, common, argc, argv, [&] {
    RequireRegularFile(scene, "scene file");
    if (!capture.empty()) RequireRegularFile(capture, "capture file");
    OutputGuard guard("lsds export-scene");
    guard.AddInput(scene, "scene file");
    guard.AddInput(capture, "capture file");
    guard.CheckOutput(options.output, "-o");
    const FrameSelection frames = FramesFlag(common);
    options.frames = frames;
    options.force = common.force;
    const Plan plan = gen::PlanFromScene(scene, capture, seed, frames);
    const int64_t written = gen::ExportScenes(plan, options);
    if (!common.quiet)
      std::cerr << "lsds export-scene: " << written << " frames -> " << options.output.string()
                << "\n";
    return kExitOk;
  });
}

}  // namespace lsds
