// Blender as lsds's second renderer (`lsds generate --renderer cycles`,
// docs/generator.md): found on PATH or given, run headless on an
// `lsds export-scene` folder through the script lsds ships
// (generator/cycles/render_frames.py).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

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
  // Also the pixel-centre depth and object index passes (NNNNNN_truth.exr);
  // without them Blender renders what a user rendering the export would.
  bool truth_passes = true;
};

// Renders `frames` of the export in `scene_folder` into `output_folder`
// (NNNNNN_rgb.exr, NNNNNN_truth.exr; render_frames.py), Blender's output going
// to `log`. Throws lsds::Error with the log's last lines when Blender fails.
void RenderWithCycles(const std::filesystem::path& blender,
                      const std::filesystem::path& scene_folder,
                      const std::filesystem::path& output_folder,
                      const std::vector<int64_t>& frames,
                      const CyclesRenderOptions& options,
                      const std::filesystem::path& log);

}  // namespace lsds::gen
