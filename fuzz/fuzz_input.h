// Shared by the libFuzzer targets of fuzz/: the readers under test take paths
// (as the CLI calls them), so each input is written to a scratch file first.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "libs/exr/exr_types.h"
#include "libs/util/limits.h"

namespace lsds::fuzz {

// A scratch folder of this process, on tmpfs when there is one (every input is
// written once), removed at exit.
inline const std::filesystem::path& ScratchDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm")
                                           ? "/dev/shm"
                                           : std::filesystem::temp_directory_path();
    std::filesystem::path d = base / ("lsds_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    static const std::filesystem::path to_remove = d;
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(to_remove, ignored);
    });
    return d;
  }();
  return dir;
}

inline void WriteBytes(const std::filesystem::path& path, const uint8_t* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

// A memory budget of 256 MiB (the CLI's --memory-budget), well under the
// fuzzers' -rss_limit_mb: a decode the budget allows must fit the limit.
inline void SmallBudget() {
  static const bool set = [] {
    SetMemoryBudget("256M");
    return true;
  }();
  (void)set;
}

// Limits small enough that a hostile header cannot make one run slow, as the
// readers' own limits bound a real run.
inline exr::ReadLimits FuzzLimits() {
  exr::ReadLimits limits;
  limits.max_width = limits.max_height = 4096;
  limits.max_pixels = 1 << 20;
  limits.max_deep_samples = 1 << 22;
  return limits;
}

}  // namespace lsds::fuzz
