// Other programs lsds runs (Blender for `lsds generate --renderer cycles`):
// found on PATH, run without a shell, their output kept in a log file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lsds {

// The path of an executable named `name` on PATH, or empty.
std::string FindOnPath(const std::string& name);

// The folder of the running executable (not of the working directory), from /proc/self/exe;
// empty when it cannot be read.
std::string ExecutableDir();

// Runs `argv` (argv[0] the executable's path; no shell) with its standard output and error
// appended to `log`, and waits for it. Returns its exit status (128 + the signal when a signal
// ended it). Throws lsds::Error naming the executable when it cannot be started.
int RunProcess(const std::vector<std::string>& argv, const std::filesystem::path& log);

}  // namespace lsds
