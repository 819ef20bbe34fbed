// lsds export-layers COLLECTION -o OUT [--to npy|png16|tiff] [--layers A,B]
//                    [--frames A:B] [--depth-step S] [--clamp-depth] [--threads T] [--force]
#include <iostream>

#include "export_layers/export_layers.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

int RunExportLayers(int argc, char** argv) {
  CLI::App app(
      "Export flat layers (depth, ids, normal, motion, ...) to .npy, 16-bit "
      "PNG or float TIFF, with layers.json giving each layer's dtype, unit, "
      "scale, offset and invalid value (docs/export-layers.md).",
      "lsds export-layers");
  layer_export::ExportOptions options;
  std::string to = "npy", layers;
  app.add_option("COLLECTION", options.collection, "collection folder (holds collection.json)")
      ->required();
  app.add_option(
         "-o,--output", options.output, "output folder: LAYER/FRAME.npy|png|tiff and layers.json")
      ->required();
  app.add_option("--to",
                 to,
                 "npy (exact float32/uint32), png16 (quantised, see "
                 "layers.json) or tiff (exact float32; ids as int32 bits)")
      ->check(CLI::IsMember({"npy", "png16", "tiff"}));
  app.add_option("--layers",
                 layers,
                 "comma-separated layer names (default: every flat layer the "
                 "target can hold)");
  app.add_option("--depth-step",
                 options.depth_step,
                 "png16: depth quantum in the collection's length unit "
                 "(default 0.001, mm for metres; 65535 steps)");
  app.add_flag("--clamp-depth",
               options.clamp_depth,
               "png16: clamp depths beyond 65535 steps instead of failing");
  CommonFlags common;
  AddCommonFlags(app, &common, "replace an existing output folder");
  return RunCommand(app, common, argc, argv, [&] {
    options.target = layer_export::ParseTarget(to);
    for (const std::string& name : Split(layers, ','))
      if (!name.empty()) options.layers.push_back(name);
    options.frames = SelectCollectionFrames(common.frames, options.collection);
    options.force = common.force;
    const layer_export::ExportSummary summary = layer_export::ExportLayers(options);
    if (!common.quiet)
      std::cerr << "export-layers: " << summary.frames << " frames, " << summary.files << " files ("
                << FormatNumber(summary.bytes / 1e6, 4) << " MB) written to "
                << options.output.string() << "\n";
    for (const layer_export::LayerSummary& layer : summary.layers) {
      if (layer.clamped_pixels > 0) {
        std::cerr << "export-layers: warning: " << layer.clamped_pixels << " pixels of '"
                  << layer.name
                  << "' outside the 16-bit range were clamped (see "
                     "layers.json; --depth-step for depth)\n";
      }
    }
    return kExitOk;
  });
}

}  // namespace lsds
