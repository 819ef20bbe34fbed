// Outputs are written atomically: to a temporary name beside the target,
// renamed at the end. A crash or an error never leaves a half-written file
// under the final name.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace lsds {

namespace fs = std::filesystem;

// A unique temporary path in the same folder as `target` (same filesystem, so
// rename is atomic).
fs::path TempPathBeside(const fs::path& target);

// Throws lsds::Error naming `path` if it exists and `force` is false.
void RefuseToOverwrite(const fs::path& path,
                       bool force,
                       const std::string& what = "output");

// Writes `content` to `path` through a temporary file and a rename.
void WriteFileAtomic(const fs::path& path, const std::string& content);

// A file stream whose content appears under `path` only when Commit() succeeds.
class AtomicFile {
 public:
  explicit AtomicFile(fs::path path,
                      std::ios::openmode mode = std::ios::out |
                                                std::ios::binary);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return stream_; }
  const fs::path& temp_path() const { return temp_path_; }
  void Commit();

 private:
  fs::path path_;
  fs::path temp_path_;
  std::ofstream stream_;
  bool committed_ = false;
};

// A folder built under a temporary name and renamed to `path` at Commit(); with
// `force` an existing folder is replaced only then, so a failed run leaves the
// old output untouched.
class AtomicDirectory {
 public:
  AtomicDirectory(fs::path path, bool force);
  ~AtomicDirectory();  // removes the temporary folder unless committed
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  const fs::path& temp_path() const { return temp_path_; }
  void Commit();

 private:
  fs::path path_;
  fs::path temp_path_;
  bool force_;
  bool committed_ = false;
};

// Reads a whole file; throws lsds::Error naming the file if it cannot.
std::string ReadFile(const fs::path& path);

}  // namespace lsds
