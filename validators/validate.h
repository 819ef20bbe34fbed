// `lsds validate` as a library: runs the selected checks over a collection and
// returns the report.
#pragma once

#include <filesystem>

#include "validators/checks.h"
#include "validators/report.h"

namespace lsds::validate {

struct ValidateOptions {
  CheckSelection checks = CheckSelection::All();
  int jobs = 0;              // worker threads; 0 = all cores
  size_t max_examples = 20;  // findings kept per check (all are counted)
  size_t batch_size =
      16;  // frames in flight at once: bounds memory, not the frame count
  int camera_grid =
      24;  // world-position correspondences per image axis for the camera solve
  bool progress = false;  // a progress line on a terminal
};

// Throws lsds::Error (exit code 2) when `root` cannot be read as a collection
// at all: no folder, no collection.json, or collection.json is not JSON.
// Everything else is a finding in the report.
Report ValidateCollection(const std::filesystem::path& root,
                          const ValidateOptions& options = {});

}  // namespace lsds::validate
