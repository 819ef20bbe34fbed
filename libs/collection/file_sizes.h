// Sizes of the files a collection names, many per folder (a layer's folder
// holds a file per frame): each folder is opened once and its files stat-ed
// relative to it, so the kernel does not look the folders of the path up again
// for every file (at 10^5 frames of 10 layers, most of `lsds info`'s time
// was those look-ups).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <unordered_map>

namespace lsds {

class FileSizes {
 public:
  explicit FileSizes(std::filesystem::path root);
  ~FileSizes();
  FileSizes(const FileSizes&) = delete;
  FileSizes& operator=(const FileSizes&) = delete;

  // The size of the regular file root/`relative` (symbolic links followed),
  // as std::filesystem::file_size gives it; nullopt where that fails (no such
  // file, not a regular file).
  std::optional<uintmax_t> Size(const std::string& relative);

 private:
  // The descriptor of root/`folder`, opened once; -1 if it cannot be opened.
  int Folder(const std::string& folder);

  std::filesystem::path root_;
  std::unordered_map<std::string, int> folders_;
};

}  // namespace lsds
