#include "tools/command.h"

#include <iostream>

#include "libs/util/error.h"

namespace lsds {

const std::vector<Command>& Commands() {
  static const std::vector<Command> commands = {
      {"generate",
       "render a scene (LSCENE/LCAP, a plan, or --demo) into a collection",
       RunGenerate},
      {"plan",
       "expand an LSCENE scene and LCAP capture into the frame plan (JSON)",
       RunPlan},
      {"info",
       "summarize a collection: frames, layers, classes, cameras, size",
       RunInfo},
      {"validate",
       "check a collection: schemas, structure, layers, cross-layer truth, "
       "camera geometry",
       RunValidate},
      {"convert",
       "truth into YOLO, COCO or CVAT files with a loss report",
       RunConvert},
      {"perturb-metadata",
       "write a perturbed copy of the metadata with the noise and errors "
       "recorded",
       RunPerturbMetadata},
      {"bundles",
       "mixed-pixel statistics of the pixel bundles; bundle-derived truth "
       "layers",
       RunBundles},
      {"backproject",
       "depth layers to point clouds (PCD/PLY), per frame or fused; --check",
       RunBackproject},
      {"synth",
       "write a synthetic collection with exact analytic truth (for tests)",
       RunSynth},
      {"import",
       "another simulator's output (ue-mrq, airsim, bop) into a collection",
       RunImport},
  };
  return commands;
}

int RunCommand(CLI::App& app,
               int argc,
               char** argv,
               const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help or the parse error
    return code == 0 ? kExitOk : kExitUsage;
  }
  try {
    return body();
  } catch (const Error& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << "\n";
    return kExitUsage;
  }
}

}  // namespace lsds
