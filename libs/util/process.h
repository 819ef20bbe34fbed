// Other programs lsds runs (Blender for `lsds generate --renderer cycles`):
// found on PATH, run without a shell, their output kept in a log file.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace lsds {

// The path of an executable named `name` on PATH, or empty.
std::string FindOnPath(const std::string& name);

// The folder of the running executable (not of the working directory), from /proc/self/exe;
// empty when it cannot be read.
std::string ExecutableDir();

// A program running beside lsds: `argv` (argv[0] the executable's path; no shell), its standard
// output and error appended to `log`. Destroying it while the program still runs ends the
// program (SIGTERM) and waits for it, so that an error in lsds leaves no orphan behind.
class ChildProcess {
 public:
  // Throws lsds::Error naming the executable when it cannot be started.
  ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& log);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  // Its exit status once it has ended (128 + the signal when a signal ended it), else nullopt.
  std::optional<int> Poll();
  int Wait();  // waits for the end; the exit status

 private:
  std::string program_;
  int pid_ = -1;
  std::optional<int> status_;
};

// Runs `argv` as a ChildProcess and waits for it; its exit status.
int RunProcess(const std::vector<std::string>& argv, const std::filesystem::path& log);

}  // namespace lsds
