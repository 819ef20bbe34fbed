// Blender as lsds's second renderer (`lsds generate --renderer cycles`,
// docs/generator.md): found on PATH or given, run headless on an
// `lsds export-scene` folder through the script lsds ships
// (generator/cycles/render_frames.py).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/util/process.h"

namespace lsds::gen {

// `given` (--blender PATH) when not empty, else `blender` on PATH. Throws
// lsds::Error naming the Debian package when there is none, or naming the path
// when it is not an executable.
std::filesystem::path FindBlender(const std::string& given);

// "3.4.1": the version `blender --version` prints. Throws lsds::Error when
// Blender does not start.
std::string BlenderVersion(const std::filesystem::path& blender);

// The shipped script: installed beside the binary (PREFIX/share/lsds/cycles),
// else the build tree's copy.
std::filesystem::path CyclesScript();

struct CyclesRenderOptions {
  int samples = 16;
  int threads = 0;  // 0: all cores
  bool denoise = false;
  // Also the depth and object index passes, in the rgb render's multilayer
  // EXR; without them Blender renders what a user rendering the export would.
  bool truth_passes = true;
};

// Blender rendering `frames` of the export in `scene_folder` into `output_folder`
// (NNNNNN_rgb.exr; render_frames.py) in the background, its output going to
// `log`, while lsds renders the same frames. Destroying it ends a Blender still running.
class CyclesRun {
 public:
  CyclesRun(const std::filesystem::path& blender,
            const std::filesystem::path& scene_folder,
            const std::filesystem::path& output_folder,
            const std::vector<int64_t>& frames,
            const CyclesRenderOptions& options,
            const std::filesystem::path& log);
  // Waits until frame `index`'s files are complete. Throws lsds::Error with the log's last lines
  // when Blender ended without them.
  void WaitForFrame(int64_t index);
  // Waits for Blender to end; throws lsds::Error with the log's last lines when it failed.
  // Returns the seconds since Blender started.
  double Finish();

 private:
  [[noreturn]] void Fail(int status) const;

  std::filesystem::path output_folder_, log_;
  std::chrono::steady_clock::time_point start_;
  ChildProcess blender_;
};

// The same, waiting for the end.
void RenderWithCycles(const std::filesystem::path& blender,
                      const std::filesystem::path& scene_folder,
                      const std::filesystem::path& output_folder,
                      const std::vector<int64_t>& frames,
                      const CyclesRenderOptions& options,
                      const std::filesystem::path& log);

}  // namespace lsds::gen
