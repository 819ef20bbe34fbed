// The benchmarks' child processes: run a command line and measure its own wall time, CPU time
// and peak memory (wait4's rusage of that child alone).
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace lsds::bench {

struct ChildRun {
  int exit_code = -1;
  double seconds = 0;
  double cpu_seconds = 0;  // user + system of the child
  double peak_mib = 0;     // maxrss of the child
};

// Runs argv with stdout and stderr to /dev/null, with `environment` ("NAME=value") added to this
// process's. Linux keeps the larger of the forked copy's and the executed program's peak RSS as
// the child's maxrss, so the calling process must itself be smaller than what it measures.
inline ChildRun RunChild(const std::vector<std::string>& args,
                         const std::vector<std::string>& environment = {}) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(nullptr);  // or the child would write this process's pending output again
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    for (const std::string& variable : environment) putenv(const_cast<char*>(variable.c_str()));
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  ChildRun run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peak_mib = usage.ru_maxrss / 1024.0;  // Linux: KiB
  run.cpu_seconds = usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
                    1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  return run;
}

}  // namespace lsds::bench
