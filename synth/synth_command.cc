// lsds synth OUT [--count N] [--size WxH] [--samples-per-axis N] [--depth
// planar|perspective] [--force]
#include <cstdio>
#include <iostream>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "synth/synthetic_collection.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

int RunSynth(int argc, char** argv) {
  CLI::App app(
      "Write a synthetic collection with exact, analytic layers and truth (a "
      "ground plane and three "
      "boxes under a nadir camera): a known-good input for testing pipelines "
      "and tools.",
      "lsds synth");
  std::string out;
  int frames = 4;
  std::string size = "640x480";
  int samples_per_axis = 2;
  std::string depth = "planar";
  app.add_option("OUT", out, "output collection folder")->required();
  app.add_option("--count", frames, "number of frames to write (default 4)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--size", size, "image size WIDTHxHEIGHT");
  app.add_option("--samples-per-axis", samples_per_axis, "bundle samples per pixel = N*N")
      ->check(CLI::Range(1, 16));
  app.add_option("--depth", depth, "declared depth kind")
      ->check(CLI::IsMember({"planar", "perspective"}));
  // --frames selects frame indices in every command (docs/cli.md); synth makes
  // a new collection, so it takes a count and says so instead of guessing.
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "replace OUT if it exists",
                 {{"--frames",
                   "synth writes a new collection: give its number of frames with "
                   "--count N (--frames selects frame indices of an existing "
                   "collection or plan in the other commands)"}});
  return RunCommand(app, common, argc, argv, [&] {
    int width = 0, height = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2 || width < 1 || height < 1 ||
        width > 16384 || height > 16384) {
      throw Error("--size must be WIDTHxHEIGHT, e.g. 640x480, got '" + size + "'");
    }
    synth::Spec spec = synth::CircleSpec(frames, width, height);
    spec.samples_per_axis = samples_per_axis;
    ParseDepthKind(depth, &spec.depth_kind);
    AtomicDirectory output(out, common.force);
    synth::WriteCollection(output.temp_path(), spec);
    output.Commit();
    if (!common.quiet)
      std::cout << "wrote " << frames << " frames (" << width << "x" << height << ") to " << out
                << "\n";
    return 0;
  });
}

}  // namespace lsds
