// lsds bundles COLLECTION [-o stats.json] [--write-layers LIST] [--frames A:B]
// [--force] ...
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "bundles/bundle_run.h"
#include "bundles/derived_layers.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

int RunBundles(int argc, char** argv) {
  CLI::App app(
      "Mixed-pixel statistics of the pixel bundles (deep `bundle` layer) of a "
      "collection, and "
      "bundle-derived truth layers (docs/bundles.md).",
      "lsds bundles");
  std::string collection, output, layers, mixed_map;
  bundle::RunOptions options;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_option(
      "-o,--output", output, "write the statistics JSON here (schemas/bundle-stats.schema.json)");
  app.add_option("--write-layers",
                 layers,
                 "comma-separated derived layers to add to the collection: "
                 "majority,purity,coverage,edge");
  app.add_option("--flying-abs",
                 options.stats.flying_absolute,
                 "flying-pixel threshold, world length units (default 0.05)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--flying-rel",
                 options.stats.flying_relative,
                 "flying-pixel threshold, share of the averaged depth (default 0.01)")
      ->check(CLI::NonNegativeNumber);
  app.add_option(
      "--mixed-map", mixed_map, "write a PNG of the mixed pixels of the first analysed frame");
  app.add_option("--batch", options.batch, "frames decoded at once (default: one per core)");
  CommonFlags common;
  AddCommonFlags(app, &common, "replace the output files and earlier derived layers");
  return RunCommand(app, common, argc, argv, [&] {
    if (!layers.empty()) options.write_layers = bundle::ParseDerivedLayerList(layers);
    options.force = common.force;
    options.frames = SelectCollectionFrames(common.frames, collection);
    options.output = output;
    options.mixed_map = mixed_map;
    const bundle::RunResult result = bundle::RunBundles(collection, options);
    const bundle::BundleStats& s = result.total;
    const double pixels = s.pixels > 0 ? static_cast<double>(s.pixels) : 1.0;
    std::printf("frames analysed     %lld (layer '%s')\n",
                static_cast<long long>(result.frames_analyzed),
                result.bundle_layer.c_str());
    std::printf("samples per pixel   %.3f\n", s.samples / pixels);
    std::printf("mixed pixels        %.4f%% (%llu)\n",
                100.0 * s.mixed_pixels / pixels,
                static_cast<unsigned long long>(s.mixed_pixels));
    std::printf("class-mixed pixels  %.4f%%\n", 100.0 * s.class_mixed_pixels / pixels);
    std::printf("mean purity         %.4f\n", s.purity_sum / pixels);
    std::printf("flying pixels       %.4f%% (%llu)\n",
                100.0 * s.flying_pixels / pixels,
                static_cast<unsigned long long>(s.flying_pixels));
    if (!options.write_layers.empty()) {
      std::printf("layers written      ");
      for (size_t i = 0; i < options.write_layers.size(); ++i) {
        std::printf("%s%s", i ? "," : "", options.write_layers[i].c_str());
      }
      std::printf("\n");
    }
    if (!output.empty()) std::printf("statistics          %s\n", output.c_str());
    return 0;
  });
}

}  // namespace lsds
