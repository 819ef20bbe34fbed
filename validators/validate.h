// `lsds validate` as a library: runs the selected checks over a collection and
// returns the report.
#pragma once

#include <filesystem>

#include "libs/util/frame_selection.h"

#include "validators/checks.h"
#include "validators/partial_report.h"
#include "validators/report.h"

namespace lsds::validate {

struct ValidateOptions {
  CheckSelection checks = CheckSelection::All();
  int jobs = 0;              // worker threads; 0 = all cores
  size_t max_examples = 20;  // findings kept per check (all are counted)
  size_t batch_size = 16;    // frames in flight at once: bounds memory, not the frame count
  int camera_grid = 24;      // world-position correspondences per image axis for the camera solve
  bool progress = false;     // a progress line on a terminal
  // `--shard I/N`: check only the frames whose index % N == I (and, in shard
  // 0, the header, metadata tables and stray files). The result is a partial
  // report; `lsds merge-reports` joins N of them into the single run's report.
  int shard_index = 0;
  int shard_count = 1;
  // `--frames`: check only the frames with index in this range (with --shard,
  // those of the shard among them). The header, the tables and stray files are
  // still checked; the statistics checks (stats.*) count the frames checked.
  FrameRange frames;
};

// Throws lsds::Error (exit code 2) when `root` cannot be read as a collection
// at all: no folder, no collection.json, or collection.json is not JSON.
// Everything else is a finding in the report.
Report ValidateCollection(const std::filesystem::path& root, const ValidateOptions& options = {});

// One shard of a run (options.shard_count >= 1): its findings, and the tallies
// that the whole-collection checks need from every shard.
PartialReport ValidateShard(const std::filesystem::path& root, const ValidateOptions& options);

}  // namespace lsds::validate
