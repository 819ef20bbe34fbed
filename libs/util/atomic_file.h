// Outputs are written atomically: to a temporary name beside the target,
// renamed at the end. A crash or an error never leaves a half-written file
// under the final name. This is the one output path of lsds: every write and
// the close are checked, the data is synced to disk before the rename, and the
// temporary file is removed on every error path.
//
// Temporary names are recognizable: `.NAME.lsds-tmp-HOST-PID-N`. The first
// output a process writes into a folder removes the leftovers there of runs
// that were killed (same host, process gone), so a killed run's temporaries
// never accumulate and are never taken for outputs.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>

namespace lsds {

namespace fs = std::filesystem;

// A unique temporary path in the same folder as `target` (same filesystem, so
// rename is atomic), named `.NAME.lsds-tmp-HOST-PID-N`.
fs::path TempPathBeside(const fs::path& target);

// True for a file name made by TempPathBeside.
bool IsTempName(const std::string& file_name);

// Removes the temporaries in `folder` (and below it with `recursive`) left by
// runs that are no longer alive on this host; returns how many were removed.
// Temporaries of live processes (including this one) are kept.
size_t RemoveStaleTemps(const fs::path& folder, bool recursive = false);

// Throws lsds::Error naming `path` if it exists and `force` is false.
void RefuseToOverwrite(const fs::path& path, bool force, const std::string& what = "output");

// Writes `content` to `path` through a temporary file and a rename.
void WriteFileAtomic(const fs::path& path, const std::string& content);

// For libraries that only write by file name and do not report write errors
// (PCL): `write` writes the file at the scratch path it is given (in memory);
// its bytes then go to `path` through the checked atomic path.
void WriteFileAtomicVia(const fs::path& path,
                        const std::function<void(const fs::path& scratch)>& write);

// A stream buffer over a file descriptor that checks every write (the first
// error is kept; later writes are refused) and supports seeking.
class CheckedFileBuf : public std::streambuf {
 public:
  explicit CheckedFileBuf(int fd);
  // The first write error (an errno value), 0 if none.
  int error() const { return error_; }
  // Writes out the buffer; false after any error.
  bool Flush();

 protected:
  int_type overflow(int_type c) override;
  std::streamsize xsputn(const char* data, std::streamsize n) override;
  int sync() override;
  pos_type seekoff(off_type off,
                   std::ios_base::seekdir dir,
                   std::ios_base::openmode which) override;
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override;

 private:
  bool WriteAll(const char* data, size_t n);
  int fd_;
  int error_ = 0;
  char buffer_[1 << 16];
};

// A file whose content appears under `path` only when Commit() succeeds.
class AtomicFile {
 public:
  explicit AtomicFile(fs::path path);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return *stream_; }
  const fs::path& path() const { return path_; }
  const fs::path& temp_path() const { return temp_path_; }
  // Flushes; throws lsds::Error naming the output if any write failed so far.
  void Check();
  // Flushes, syncs, closes and renames into place; throws lsds::Error naming
  // the output on any failure (the temporary file is then removed).
  void Commit();

 private:
  [[noreturn]] void Fail(const std::string& what, int error);
  fs::path path_;
  fs::path temp_path_;
  int fd_ = -1;
  std::unique_ptr<CheckedFileBuf> buffer_;
  std::unique_ptr<std::ostream> stream_;
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
