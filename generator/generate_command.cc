// lsds generate: render a plan (from LSCENE/LCAP, a plan JSON, or the built-in
// demo) into a collection. The work lives in generator/generate.h; this file
// parses flags.
#include <csignal>
#include <cstring>
#include <iostream>
#include <optional>

#include <unistd.h>

#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/plan_source.h"
#include "generator/render/film.h"
#include "generator/render/post_process.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/util/error.h"
#include "libs/util/limits.h"
#include "libs/util/output_guard.h"
#include "libs/util/strings.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {
namespace {

// The message printed on Ctrl-C, composed before rendering starts: a signal
// handler may only write() what already exists.
std::string interrupt_message;

extern "C" void OnInterrupt(int signal_number) {
  const ssize_t ignored = write(STDERR_FILENO, interrupt_message.data(), interrupt_message.size());
  (void)ignored;
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

// On SIGINT/SIGTERM, tells the user how to keep the frames already rendered:
// --resume (not --force, which deletes them).
void InstallResumeHint(const std::string& command_line) {
  interrupt_message =
      "\nlsds generate: interrupted; the complete frames are "
      "kept: run\n  " +
      command_line + " --resume\nto finish the collection\n";
  std::signal(SIGINT, OnInterrupt);
  std::signal(SIGTERM, OnInterrupt);
}

}  // namespace

// The flag declarations, one statement per flag (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
int RunGenerate(int argc, char** argv) {
  CLI::App app{
      "Render an LSCENE/LCAP scene (or a plan) into a collection with every "
      "layer and truth",
      "lsds generate"};
  std::string scene, capture, plan_file, shard, depth = "planar", demo_size = "512x512",
                                                bundle_layout, worldposition_layout, motion_layout,
                                                renderer = "reference";
  std::optional<uint64_t> seed;
  gen::GenerateOptions options;
  bool demo = false, compact = false;
  int demo_frames = 24;
  app.add_option("SCENE", scene, "LSCENE file (text or JSON)");
  app.add_option("CAPTURE", capture, "LCAP file (text or JSON)");
  app.add_option("-o,--output",
                 options.output,
                 "output collection folder (default: the capture's Capture "
                 "Settings folder)");
  app.add_option("--seed", seed, "random seed of the plan and of the sampler (default 0)");
  AddShardOption(app, &shard, "render only the frames whose index % N == I (I/N)");
  app.add_option("--spp", options.spp, "samples per pixel, a square: 1, 4, 9, 16, ... (default 4)");
  app.add_option(
      "--jitter", options.jitter, "jitter of each stratified sample in its cell, [0, 1]");
  app.add_option("--depth", depth, "depth layer kind: planar (default) or perspective");
  app.add_option(
      "--zip-level", options.zip_level, "zlib level of ZIP layers, 0-9 (default 1: fast)");
  app.add_flag("--compact",
               compact,
               "store worldposition and motion as lossless UINT residuals (dX, dY, dZ) from "
               "the depth's prediction, as the bundle is by default: about half the bytes, "
               "decoded by every lsds command and `import lsds`, but not by other EXR readers");
  app.add_option("--bundle-layout",
                 bundle_layout,
                 "storage of the deep bundle layer: residual (default; lossless, derived "
                 "positions and classes, depths and normals as UINT differences from their "
                 "prediction, decoded by every lsds command), compact (derived positions and "
                 "classes, float depths and normals) or full (every channel of every sample)");
  app.add_option("--worldposition-layout",
                 worldposition_layout,
                 "storage of the worldposition layer: float (default; plain X, Y, Z that any "
                 "EXR reader gets right) or residual (lossless UINT differences from the "
                 "position predicted by depth and camera, as --compact)");
  app.add_option("--motion-layout",
                 motion_layout,
                 "storage of the motion layer: float (default; plain X, Y that any EXR reader "
                 "gets right) or residual (lossless UINT differences from the motion of a "
                 "static world seen by the shot's previous camera, as --compact)");
  app.add_option("--renderer",
                 renderer,
                 "what renders the rgb layer: reference (default; lsds's Embree renderer) or "
                 "cycles (Blender Cycles on the exported scene, `blender` on PATH; every truth "
                 "layer still comes from lsds's ray casts, and Cycles' depth and object index "
                 "passes are checked against them)");
  app.add_option("--blender", options.blender, "Blender's executable for --renderer cycles");
  app.add_flag("--denoise",
               options.denoise,
               "--renderer cycles: denoise the rgb (OpenImageDenoise, when Blender has it)");
  app.add_flag("--resume", options.resume, "keep the complete frames of an interrupted run");
  app.add_option("--plan", plan_file, "render a plan JSON file (lsds plan -o) instead of SCENE");
  app.add_flag("--demo", demo, "render the built-in demo scene instead of SCENE");
  app.add_option("--demo-frames", demo_frames, "frames of the demo scene (default 24)");
  app.add_option("--demo-size", demo_size, "image size of the demo scene, WxH (default 512x512)");
  CommonFlags common;
  AddCommonFlags(app, &common, "replace an existing output folder");
  return RunCommand(app, common, argc, argv, [&]() {
    gen::PlanRequest request;
    request.scene = scene;
    request.capture = capture;
    request.plan_file = plan_file;
    request.seed = seed;
    request.frames = FramesFlag(common);
    options.frames = request.frames;
    options.threads = common.threads;
    options.force = common.force;
    if (!shard.empty()) ParseShard(shard, &options.shard_index, &options.shard_count);
    options.depth_kind = ParseDepthFlag(depth);
    // --compact first; a layer's own --*-layout flag then overrides it.
    if (compact) options.layouts.UseCompact();
    if (!bundle_layout.empty() && !ParseBundleLayout(bundle_layout, &options.layouts.bundle)) {
      throw Error("--bundle-layout " + bundle_layout + ": expected residual, compact or full");
    }
    if (!worldposition_layout.empty() &&
        !ParseFlatLayout(worldposition_layout, &options.layouts.worldposition)) {
      throw Error("--worldposition-layout " + worldposition_layout +
                  ": expected float or residual");
    }
    if (!motion_layout.empty() && !ParseFlatLayout(motion_layout, &options.layouts.motion)) {
      throw Error("--motion-layout " + motion_layout + ": expected float or residual");
    }
    if (renderer == "cycles") {
      options.renderer = gen::Renderer::kCycles;
    } else if (renderer != "reference") {
      throw Error("--renderer " + renderer + ": expected reference or cycles");
    }
    if (!options.blender.empty() && options.renderer != gen::Renderer::kCycles)
      throw Error("--blender applies to --renderer cycles only");
    options.progress = !common.quiet;
    if (demo) {
      gen::DemoOptions demo_options;
      demo_options.frames = demo_frames;
      const std::vector<std::string> size = Split(demo_size, 'x');
      try {
        if (size.size() != 2) throw std::invalid_argument("size");
        demo_options.width = std::stoi(size[0]);
        demo_options.height = std::stoi(size[1]);
      } catch (const std::exception&) {
        throw Error("--demo-size " + demo_size + ": expected WxH, e.g. 512x512");
      }
      CheckImageBudget(demo_options.width,
                       demo_options.height,
                       static_cast<int64_t>(gen::Film::BytesPerPixel(options.spp)),
                       1,
                       "the demo image",
                       "--demo-size");
      request.demo = demo_options;
    }
    const Plan plan = gen::PlanForRendering(request);
    if (options.output.empty()) {
      // LCAP Capture Settings may name the output folder (relative to the
      // current directory); -o wins when both are given.
      const std::string folder = plan.capture_settings.value("folder", std::string());
      if (folder.empty())
        throw Error(
            "no output folder: give -o OUT (or a Capture Settings "
            "folder in the LCAP camera)");
      options.output = folder;
    }
    OutputGuard guard("lsds generate");
    guard.AddInput(scene, "scene file");
    guard.AddInput(capture, "capture file");
    guard.AddInput(plan_file, "plan file");
    guard.CheckOutput(options.output, "-o");
    std::string command_line = "lsds generate";
    for (int i = 1; i < argc; ++i) {
      if (std::strcmp(argv[i], "--force") != 0 && std::strcmp(argv[i], "--resume") != 0)
        command_line += std::string(" ") + argv[i];
    }
    InstallResumeHint(command_line);
    // Post-process names that are no effect are recorded, not applied: say so; and what planning
    // found doubtful.
    if (!common.quiet) {
      for (const std::string& w : gen::UnknownPostProcess(plan.post_process))
        std::cerr << "lsds generate: warning: " << w << "\n";
      for (const std::string& w : plan.warnings)
        std::cerr << "lsds generate: warning: " << w << "\n";
    }
    const gen::GenerateSummary summary = gen::GenerateCollection(plan, options);
    if (!common.quiet) {
      const double per_frame =
          summary.frames_rendered > 0 ? summary.total_seconds / summary.frames_rendered : 0;
      std::cerr << "lsds generate: " << summary.frames_rendered << " frames rendered, "
                << summary.frames_skipped << " kept, " << summary.total_seconds << " s ("
                << per_frame << " s/frame: render " << summary.render_seconds << " s, write "
                << summary.write_seconds << " s, "
                << (summary.render_seconds > 0 ? summary.rays / summary.render_seconds / 1e6 : 0)
                << " Mrays/s) -> " << options.output.string() << "\n";
      if (options.renderer == gen::Renderer::kCycles) {
        const nlohmann::json agreement = gen::AgreementSummaryJson(summary.cycles_agreement);
        std::cerr << "lsds generate: Blender Cycles: export " << summary.export_seconds
                  << " s, Blender " << summary.cycles_seconds
                  << " s; depth and object index against lsds's layers: max relative depth "
                     "error "
                  << agreement["max_relative_depth_error"].get<double>()
                  << ", max share of pixels whose id differs "
                  << agreement["max_id_mismatch_share"].get<double>() << "\n";
      }
      std::cerr << gen::FormatRequirementSummary(plan, summary.requirements);
    }
    return kExitOk;
  });
}

}  // namespace lsds
