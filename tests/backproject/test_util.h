// Helpers shared by the backproject tests: scratch folders, synthetic
// collections, the CLI.
#pragma once

#include <filesystem>
#include <string>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

// A fresh empty folder under the system temp folder, removed by the destructor.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name);
  ~ScratchDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& leaf) const { return path_ / leaf; }

 private:
  std::filesystem::path path_;
};

// Writes `spec` into `root` and returns root.
std::filesystem::path WriteSynth(const std::filesystem::path& root, const synth::Spec& spec);

// Runs `lsds ARGS` with stdout and stderr captured; returns the exit code.
int RunLsds(const std::string& args, std::string* output = nullptr);

// Names of the entries of `dir` (files and folders), sorted.
std::string ListDir(const std::filesystem::path& dir);

}  // namespace lsds::testing
