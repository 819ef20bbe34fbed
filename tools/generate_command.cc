// lsds generate: render a plan (from LSCENE/LCAP, a plan JSON, or the built-in
// demo) into a collection. The work lives in generator/generate.h; this file
// parses flags.
#include <iostream>
#include <optional>

#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/plan_source.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"

namespace lsds {
namespace {

// "A:B" (half-open), "A:" or ":B".
void ParseFrames(const std::string& text, gen::GenerateOptions* options) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos)
    throw Error("--frames " + text + ": expected A:B (frames A to B-1)");
  try {
    const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
    if (!a.empty()) options->first_frame = std::stoll(a);
    if (!b.empty()) options->last_frame = std::stoll(b);
  } catch (const std::exception&) {
    throw Error("--frames " + text + ": expected integers A:B");
  }
}

void ParseShard(const std::string& text, gen::GenerateOptions* options) {
  const std::vector<std::string> parts = Split(text, '/');
  try {
    if (parts.size() != 2) throw std::invalid_argument("shard");
    options->shard_index = std::stoi(parts[0]);
    options->shard_count = std::stoi(parts[1]);
  } catch (const std::exception&) {
    throw Error("--shard " + text + ": expected I/N, e.g. 0/4");
  }
}

}  // namespace

int RunGenerate(int argc, char** argv) {
  CLI::App app{
      "Render an LSCENE/LCAP scene (or a plan) into a collection with every "
      "layer and truth",
      "lsds generate"};
  std::string scene, capture, plan_file, frames, shard, depth = "planar",
                                                        demo_size = "512x512";
  std::optional<uint64_t> seed;
  gen::GenerateOptions options;
  bool demo = false, quiet = false;
  int demo_frames = 24;
  app.add_option("SCENE", scene, "LSCENE file (text or JSON)");
  app.add_option("CAPTURE", capture, "LCAP file (text or JSON)");
  app.add_option("-o,--output",
                 options.output,
                 "output collection folder (default: the capture's Capture "
                 "Settings folder)");
  app.add_option(
      "--seed", seed, "random seed of the plan and of the sampler (default 0)");
  app.add_option(
      "--frames", frames, "render frames A to B-1 only (A:B, A: or :B)");
  app.add_option("--shard", shard, "render frames whose index % N == I (I/N)");
  app.add_option("--spp",
                 options.spp,
                 "samples per pixel, a square: 1, 4, 9, 16, ... (default 4)");
  app.add_option("--jitter",
                 options.jitter,
                 "jitter of each stratified sample in its cell, [0, 1]");
  app.add_option(
      "--threads", options.threads, "worker threads (default: all cores)");
  app.add_option(
      "--depth", depth, "depth layer kind: planar (default) or perspective");
  app.add_option("--zip-level",
                 options.zip_level,
                 "zlib level of ZIP layers, 0-9 (default 1: fast)");
  app.add_flag("--force", options.force, "replace an existing output folder");
  app.add_flag("--resume",
               options.resume,
               "keep the complete frames of an interrupted run");
  app.add_option("--plan",
                 plan_file,
                 "render a plan JSON file (lsds plan -o) instead of SCENE");
  app.add_flag(
      "--demo", demo, "render the built-in demo scene instead of SCENE");
  app.add_option(
      "--demo-frames", demo_frames, "frames of the demo scene (default 24)");
  app.add_option("--demo-size",
                 demo_size,
                 "image size of the demo scene, WxH (default 512x512)");
  app.add_flag("-q,--quiet", quiet, "no progress bar and no summary");
  return RunCommand(app, argc, argv, [&]() {
    if (!frames.empty()) ParseFrames(frames, &options);
    if (!shard.empty()) ParseShard(shard, &options);
    if (!ParseDepthKind(depth, &options.depth_kind)) {
      throw Error("--depth " + depth + ": expected planar or perspective");
    }
    options.progress = !quiet;
    const int sources =
        (demo ? 1 : 0) + (plan_file.empty() ? 0 : 1) + (scene.empty() ? 0 : 1);
    if (sources != 1)
      throw Error("give exactly one of SCENE [CAPTURE], --plan FILE or --demo");
    Plan plan;
    if (demo) {
      gen::DemoOptions demo_options;
      demo_options.frames = demo_frames;
      demo_options.seed = seed.value_or(0);
      const std::vector<std::string> size = Split(demo_size, 'x');
      try {
        if (size.size() != 2) throw std::invalid_argument("size");
        demo_options.width = std::stoi(size[0]);
        demo_options.height = std::stoi(size[1]);
      } catch (const std::exception&) {
        throw Error("--demo-size " + demo_size +
                    ": expected WxH, e.g. 512x512");
      }
      plan = gen::MakeDemoPlan(demo_options);
    } else if (!plan_file.empty()) {
      plan = gen::LoadPlanJson(plan_file);
      if (seed) plan.seed = *seed;
    } else {
      plan = gen::PlanFromScene(scene,
                                capture,
                                seed.value_or(0),
                                options.first_frame,
                                options.last_frame);
    }
    if (options.output.empty()) {
      // LCAP Capture Settings may name the output folder (relative to the
      // current directory); -o wins when both are given.
      const std::string folder =
          plan.capture_settings.value("folder", std::string());
      if (folder.empty())
        throw Error(
            "no output folder: give -o OUT (or a Capture Settings "
            "folder in the LCAP camera)");
      options.output = folder;
    }
    const gen::GenerateSummary summary = gen::GenerateCollection(plan, options);
    if (!quiet) {
      const double per_frame =
          summary.frames_rendered > 0
              ? summary.total_seconds / summary.frames_rendered
              : 0;
      std::cerr << "lsds generate: " << summary.frames_rendered
                << " frames rendered, " << summary.frames_skipped << " kept, "
                << summary.total_seconds << " s (" << per_frame
                << " s/frame: render " << summary.render_seconds << " s, write "
                << summary.write_seconds << " s, "
                << (summary.render_seconds > 0
                        ? summary.rays / summary.render_seconds / 1e6
                        : 0)
                << " Mrays/s) -> " << options.output.string() << "\n";
    }
    return kExitOk;
  });
}

}  // namespace lsds
