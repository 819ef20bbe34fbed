// One check for every command that writes: no output may be, contain or lie
// inside an input of the same command, with or without --force
// (docs/reliability.md). Paths are compared in canonical form (absolute,
// symlinks resolved), so `-o ./C/../C` or a symlink to the collection is seen
// through.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lsds {

class OutputGuard {
 public:
  // `command` names the caller in messages ("lsds convert").
  explicit OutputGuard(std::string command);

  // An input file or folder (`what`: "collection folder", "scene file", ...).
  // No output may be it, contain it or lie inside it. Empty paths are ignored.
  void AddInput(const std::filesystem::path& path, const std::string& what);

  // Every symlink directly in `folder` adds its target as an input: a
  // collection whose layer folder links elsewhere protects that place too.
  // (One level only: a million per-frame links would cost a million stats.)
  void AddSymlinkTargetsIn(const std::filesystem::path& folder);

  // A folder the command documents writing into (perturb-metadata's variant,
  // bundles' derived layers): outputs may lie inside it, but may not be it or
  // contain it. The files inside it that the command reads must be added with
  // AddInput.
  void AddContainer(const std::filesystem::path& folder, const std::string& what);

  // Throws lsds::Error (exit 2) naming the output, the flag that gave it and
  // the input it would destroy. Empty outputs are ignored.
  void CheckOutput(const std::filesystem::path& output, const std::string& flag) const;

  size_t input_count() const { return inputs_.size(); }

 private:
  struct Entry {
    std::filesystem::path given;      // as the user wrote it
    std::filesystem::path canonical;  // absolute, symlinks resolved
    std::string what;
    bool container = false;
  };
  std::string command_;
  std::vector<Entry> inputs_;
};

// Absolute, lexically normal, symlinks of the existing prefix resolved.
std::filesystem::path CanonicalPath(const std::filesystem::path& path);

// True when `inner` is `outer` or lies below it (both canonical).
bool PathWithin(const std::filesystem::path& inner, const std::filesystem::path& outer);

}  // namespace lsds
