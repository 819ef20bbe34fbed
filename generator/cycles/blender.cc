#include "generator/cycles/blender.h"

#include <unistd.h>

#include <regex>
#include <thread>

#include "generator/cycles/script_path.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/process.h"
#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

// The last `count` lines of a log, for an error message.
std::string LogTail(const fs::path& log, size_t count) {
  std::error_code ec;
  if (!fs::is_regular_file(log, ec)) return "";
  const std::vector<std::string> lines = Split(ReadFile(log), '\n');
  std::string tail;
  for (size_t i = lines.size() > count ? lines.size() - count : 0; i < lines.size(); ++i)
    tail += "\n  " + lines[i];
  return tail;
}

}  // namespace

fs::path FindBlender(const std::string& given) {
  if (given.empty()) {
    const std::string found = FindOnPath("blender");
    if (found.empty())
      throw Error(
          "--renderer cycles needs Blender: none on PATH; install the Debian package `blender` "
          "(apt-get install blender, or scripts/install-deps.sh) or give --blender PATH");
    return found;
  }
  std::error_code ec;
  if (!fs::is_regular_file(given, ec) || access(given.c_str(), X_OK) != 0)
    throw Error("--blender " + given +
                ": not an executable file (install the Debian package `blender`, or give the "
                "path of Blender's executable)");
  return fs::absolute(given);
}

std::string BlenderVersion(const fs::path& blender) {
  const fs::path log = TempPathBeside(fs::temp_directory_path() / "lsds-blender-version.log");
  const int status = RunProcess({blender.string(), "--factory-startup", "--version"}, log);
  std::string text;
  std::error_code ec;
  if (fs::is_regular_file(log, ec)) text = ReadFile(log);
  fs::remove(log, ec);
  std::smatch match;
  if (status != 0 ||
      !std::regex_search(text, match, std::regex("Blender ([0-9]+\\.[0-9]+(\\.[0-9]+)?)")))
    throw Error(blender.string() + " --version did not name a Blender version (exit status " +
                std::to_string(status) + ")");
  return match[1];
}

fs::path CyclesScript() {
  if (const std::string exe_dir = ExecutableDir(); !exe_dir.empty()) {
    fs::path installed =
        (fs::path(exe_dir) / ".." / "share" / "lsds" / "cycles" / "render_frames.py")
            .lexically_normal();
    std::error_code ec;
    if (fs::is_regular_file(installed, ec)) return installed;
  }
  fs::path built = CyclesScriptBuildPath();
  std::error_code ec;
  if (fs::is_regular_file(built, ec)) return built;
  throw Error(
      "the Cycles script render_frames.py is neither installed (PREFIX/share/lsds/cycles) "
      "nor in the build tree (" +
      built.string() + ")");
}

namespace {

std::vector<std::string> BlenderArguments(const fs::path& blender,
                                          const fs::path& scene_folder,
                                          const fs::path& output_folder,
                                          const std::vector<int64_t>& frames,
                                          const CyclesRenderOptions& options) {
  std::string list;
  for (const int64_t f : frames) list += (list.empty() ? "" : ",") + std::to_string(f);
  std::vector<std::string> argv = {blender.string(),
                                   "-b",
                                   "--factory-startup",
                                   "-noaudio",
                                   "--python-exit-code",
                                   "1",
                                   "--python",
                                   CyclesScript().string(),
                                   "--",
                                   scene_folder.string(),
                                   output_folder.string(),
                                   "--frames",
                                   list,
                                   "--samples",
                                   std::to_string(options.samples),
                                   "--threads",
                                   std::to_string(options.threads)};
  if (options.denoise) argv.emplace_back("--denoise");
  if (!options.truth_passes) argv.emplace_back("--no-truth");
  return argv;
}

}  // namespace

CyclesRun::CyclesRun(const fs::path& blender,
                     const fs::path& scene_folder,
                     const fs::path& output_folder,
                     const std::vector<int64_t>& frames,
                     const CyclesRenderOptions& options,
                     const fs::path& log)
    : output_folder_(output_folder),
      log_(log),
      start_(std::chrono::steady_clock::now()),
      blender_(BlenderArguments(blender, scene_folder, output_folder, frames, options), log) {}

void CyclesRun::Fail(int status) const {
  throw Error("Blender Cycles failed (exit status " + std::to_string(status) + "; log " +
              log_.string() + "):" + LogTail(log_, 12));
}

void CyclesRun::WaitForFrame(int64_t index) {
  const fs::path last = output_folder_ / (FrameStem(index) + "_rgb.exr");
  while (true) {
    std::error_code ec;
    if (fs::exists(last, ec)) return;
    if (const std::optional<int> status = blender_.Poll()) {
      if (fs::exists(last, ec)) return;
      if (*status != 0) Fail(*status);
      throw Error("Blender Cycles ended without rendering frame " + std::to_string(index) +
                  " (log " + log_.string() + "):" + LogTail(log_, 12));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

double CyclesRun::Finish() {
  const int status = blender_.Wait();
  if (status != 0) Fail(status);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void RenderWithCycles(const fs::path& blender,
                      const fs::path& scene_folder,
                      const fs::path& output_folder,
                      const std::vector<int64_t>& frames,
                      const CyclesRenderOptions& options,
                      const fs::path& log) {
  CyclesRun run(blender, scene_folder, output_folder, frames, options, log);
  run.Finish();
}

}  // namespace lsds::gen
