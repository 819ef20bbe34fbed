// Shared helpers for the perturb-metadata tests: temporary folders and
// synthetic collections.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>

#include "libs/util/atomic_file.h"
#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds::testing_perturb {

namespace fs = std::filesystem;

// A fresh folder under the system temporary folder, removed at the end of the
// test.
using TempDir = lsds::testing::TempDir;

// A synthetic collection (ground + the default boxes) seen by a nadir camera at
// 20 m moving +x by `step` metres per frame, 0.1 s apart; only the instance
// layer is written so that thousands of frames stay cheap.
inline synth::Spec NadirSpec(int frames, int width = 8, int height = 8, double step = 0.01) {
  synth::Spec spec = synth::DefaultSpec();
  spec.width = width;
  spec.height = height;
  spec.samples_per_axis = 1;
  spec.layers = {"instanceid"};
  spec.cam_from_world.clear();
  for (int k = 0; k < frames; ++k) {
    spec.cam_from_world.push_back(synth::NadirCamFromWorld({-1.5 + step * k, 0.0, 20.0}));
  }
  return spec;
}

inline fs::path WriteNadirCollection(
    const fs::path& root, int frames, int width = 8, int height = 8, bool targets = true) {
  synth::Spec spec = NadirSpec(frames, width, height);
  if (!targets) spec.boxes.clear();  // ground only: much cheaper truth for long collections
  synth::WriteCollection(root, spec);
  return root;
}

inline std::string ReadText(const fs::path& path) { return ReadFile(path); }

// The text of collection.json from its "frames" array on: the part that must
// never change.
inline std::string FramesText(const fs::path& collection_json) {
  const std::string text = ReadFile(collection_json);
  const size_t at = text.find("\"frames\": [");
  return at == std::string::npos ? "" : text.substr(at);
}

}  // namespace lsds::testing_perturb
