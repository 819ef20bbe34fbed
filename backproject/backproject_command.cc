// lsds backproject COLLECTION -o OUT [--fuse] [--voxel M] [--frame
// world|camera] [--use-metadata FILE]
//                  [--check] [--normals] [--stride K] [--frames A:B] [--format
//                  pcd|ply] [--force]
#include <cctype>
#include <cstdio>
#include <iostream>

#include "backproject/backproject_run.h"
#include "libs/collection/collection_guard.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/error.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

// The flag declarations, one statement per flag (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
int RunBackproject(int argc, char** argv) {
  CLI::App app(
      "Back-project depth layers into point clouds (PCD or PLY): one per frame "
      "into a folder, or one "
      "fused cloud with --fuse; --check compares with the worldposition layer.",
      "lsds backproject");
  pointcloud::BackprojectOptions options;
  std::string frame = "world";
  double tolerance = -1;
  bool no_color = false, no_labels = false;
  app.add_option("COLLECTION", options.collection, "collection folder (holds collection.json)")
      ->required();
  app.add_option("-o,--output",
                 options.output,
                 "output: a folder of FRAME.pcd|ply files, or with --fuse one "
                 ".pcd or .ply file");
  app.add_flag("--fuse", options.fuse, "write one cloud of all selected frames");
  app.add_option("--voxel",
                 options.voxel,
                 "with --fuse: keep one point per voxel of this size (world "
                 "units of the output frame)");
  app.add_option("--frame",
                 frame,
                 "coordinates of the points: world (declared frame and unit) or camera "
                 "(OpenCV, world unit)")
      ->check(CLI::IsMember({"world", "camera"}));
  app.add_option("--use-metadata",
                 options.metadata,
                 "use this metadata variant's poses and intrinsics instead of "
                 "the truth (path, or relative "
                 "to the collection)");
  app.add_flag(
      "--check", options.check, "report per-frame max/RMS distance to the worldposition layer");
  app.add_option("--tolerance",
                 tolerance,
                 "with --check: exit 1 when a frame's max error exceeds this "
                 "(world units)");
  app.add_flag("--normals", options.normals, "add per-point normals from the normal layer");
  app.add_option("--stride", options.stride, "use every K-th pixel in x and y (quick previews)")
      ->check(CLI::PositiveNumber);
  app.add_option(
         "--format", options.per_frame_format, "per-frame file format: pcd (default) or ply")
      ->check(CLI::IsMember({"pcd", "ply"}));
  std::string ply_ids = "int";
  app.add_option("--ply-ids",
                 ply_ids,
                 "PLY label and instance type: int (default; Open3D reads it) or uint "
                 "(PCL's point types read it)")
      ->check(CLI::IsMember({"int", "uint"}));
  app.add_flag("--no-color", no_color, "leave out the rgb field");
  app.add_flag("--no-labels", no_labels, "leave out the label (class) and instance fields");
  CommonFlags common;
  AddCommonFlags(app, &common, "replace an existing output");
  return RunCommand(app, common, argc, argv, [&] {
    options.ply_ids = pointcloud::PlyIdsFromName(ply_ids);
    options.frame =
        frame == "camera" ? pointcloud::OutputFrame::kCamera : pointcloud::OutputFrame::kWorld;
    options.frames = SelectCollectionFrames(common.frames, options.collection);
    options.force = common.force;
    // `-o f0.pcd` without --fuse: a file, not a folder. One selected frame is
    // written to it (its cloud is the fused cloud of that frame); several are
    // a usage error in the library that says what to do.
    std::string extension = options.output.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(c));
    if (!options.fuse && (extension == ".pcd" || extension == ".ply")) {
      int64_t selected = 0;
      for (const int64_t index : CollectionFrameIndices(options.collection))
        if (options.frames.Contains(index)) ++selected;
      if (selected == 1) options.fuse = true;
    }
    OutputGuard guard("lsds backproject");
    // "Not a collection" says more than "the output lies inside the folder".
    CheckCollectionFolder(options.collection);
    GuardCollection(&guard, options.collection, CollectionAccess::kReadOnly);
    guard.AddInput(options.metadata, "metadata file");
    if (!options.metadata.empty())
      guard.AddInput(options.collection / options.metadata, "metadata file");
    guard.CheckOutput(options.output, "-o");
    options.colors = !no_color;
    options.labels = !no_labels;
    if (tolerance >= 0 && !options.check) options.check = true;
    bool exceeded = false;
    if (options.check)
      std::printf("%8s %10s %14s %14s\n", "frame", "compared", "max_error", "rms_error");
    const pointcloud::BackprojectSummary summary =
        pointcloud::RunBackproject(options, [&](const pointcloud::FrameReport& r) {
          if (!r.checked) return;
          std::printf("%8lld %10lld %14.6g %14.6g\n",
                      static_cast<long long>(r.index),
                      static_cast<long long>(r.check.compared),
                      r.check.max_error,
                      r.check.rms());
          if (tolerance >= 0 && r.check.max_error > tolerance) exceeded = true;
        });
    if (options.check) {
      std::printf("%8s %10lld %14.6g %14.6g   (%s)\n",
                  "all",
                  static_cast<long long>(summary.check.compared),
                  summary.check.max_error,
                  summary.check.rms(),
                  summary.world_unit.c_str());
    }
    if (!options.output.empty() && !common.quiet) {
      std::cerr << "backproject: " << summary.frames << " frames, " << summary.points_backprojected
                << " points back-projected, " << summary.points_written << " written to "
                << options.output.string() << "\n";
    }
    return exceeded ? kExitFindings : kExitOk;
  });
}

}  // namespace lsds
