// lsds import FORMAT SOURCE -o COLLECTION [--objects FILE] [--settings FILE] [--up-axis z|y]
// [--fov-window data|display] [--all-labels] [--compact] [--allow-links-outside] [--force]
#include <iostream>

#include "importers/import_collection.h"
#include "importers/registry.h"
#include "libs/util/output_guard.h"
#include "libs/util/strings.h"
#include "tools/command.h"

namespace lsds {

int RunImport(int argc, char** argv) {
  CLI::App app(
      "Bring another simulator's output into a collection (docs/import.md): "
      "layers converted to the collection's units and frames, missing truth "
      "derived from the layers. Formats: " +
          Join(import::ImporterNames(), ", ") + ".",
      "lsds import");
  std::string format, source, output;
  import::ImportOptions options;
  std::string objects, settings;
  bool compact = false;
  app.add_option("FORMAT", format, "source format")->required();
  app.add_option("SOURCE", source, "the simulator's output folder")->required();
  app.add_option("-o,--output", output, "the collection folder to write")->required();
  app.add_option("--objects",
                 objects,
                 "sidecar with the objects' classes, ids and 3D boxes "
                 "(default SOURCE/lsds_objects.json)");
  app.add_option("--settings",
                 settings,
                 "the simulator's settings (airsim: settings.json with the "
                 "camera mount; default SOURCE/settings.json)");
  app.add_option("--up-axis",
                 options.up_axis,
                 "the USD stage's up axis, which Replicator does not write "
                 "(replicator: z or y; default z)")
      ->check(CLI::IsMember({"z", "y"}));
  app.add_option("--fov-window",
                 options.fov_window,
                 "the EXR window the camera's FOV spans (ue-mrq): data (default: Movie Render "
                 "Queue's, the rendered image with any overscan) or display (files whose FOV "
                 "is the full frame's and whose data window is a crop)")
      ->check(CLI::IsMember({"data", "display"}));
  app.add_flag("--all-labels",
               options.all_labels,
               "make every label the source defines a class, also those no frame uses "
               "(solo; default: only the labels used)");
  app.add_flag("--compact",
               compact,
               "store worldposition as lossless UINT residuals (dX, dY, dZ) from the depth's "
               "prediction, as lsds generate --compact: a fraction of the bytes, decoded by "
               "every lsds command and `import lsds`, but not by other EXR readers");
  app.add_flag("--allow-links-outside",
               options.allow_links_outside,
               "read files of the source that are symbolic links to places outside it "
               "(deliberately linked data); names in the source's data must still be "
               "relative paths inside it");
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "replace the output if it exists",
                 {{"--frames",
                   "lsds import brings every frame of the source; select frames of the "
                   "collection afterwards (e.g. lsds convert --frames)"}});
  return RunCommand(app, common, argc, argv, [&] {
    OutputGuard guard("lsds import");
    guard.AddInput(source, "source folder");
    guard.AddInput(objects, "objects file");
    guard.AddInput(settings, "settings file");
    guard.CheckOutput(output, "-o");
    options.objects = objects;
    options.settings = settings;
    if (compact) options.layouts.UseCompact();
    const import::ImportResult result =
        import::ImportCollection(format, source, output, options, common.force);
    // Warnings are printed even with -q: they say what the collection lacks.
    for (const std::string& warning : result.warnings)
      std::cerr << "lsds import: warning: " << warning << "\n";
    if (!common.quiet)
      std::cout << "imported " << result.frames << " frames, " << result.objects
                << " object entries from " << source << " (" << format << ") to " << output << "\n";
    return 0;
  });
}

}  // namespace lsds
