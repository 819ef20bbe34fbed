#include "libs/util/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <sstream>
#include <system_error>

#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds {

fs::path TempPathBeside(const fs::path& target) {
  static std::atomic<uint64_t> counter{0};
  std::ostringstream name;
  name << "." << target.filename().string() << ".tmp-" << ::getpid() << "-"
       << counter++;
  return target.parent_path() / name.str();
}

void RefuseToOverwrite(const fs::path& path,
                       bool force,
                       const std::string& what) {
  std::error_code ec;
  if (!force && fs::exists(path, ec)) {
    throw Error(what + " exists; pass --force to overwrite it",
                Location(path.string()));
  }
}

void WriteFileAtomic(const fs::path& path, const std::string& content) {
  AtomicFile file(path);
  file.stream().write(content.data(),
                      static_cast<std::streamsize>(content.size()));
  file.Commit();
}

AtomicFile::AtomicFile(fs::path path, std::ios::openmode mode)
    : path_(std::move(path)), temp_path_(TempPathBeside(path_)) {
  stream_.open(temp_path_, mode);
  if (!stream_)
    throw Error("cannot open for writing", Location(path_.string()));
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    stream_.close();
    std::error_code ec;
    fs::remove(temp_path_, ec);
  }
}

void AtomicFile::Commit() {
  stream_.flush();
  const bool ok = static_cast<bool>(stream_);
  stream_.close();
  if (!ok) throw Error("write failed", Location(path_.string()));
  std::error_code ec;
  fs::rename(temp_path_, path_, ec);
  if (ec)
    throw Error("cannot rename into place: " + ec.message(),
                Location(path_.string()));
  committed_ = true;
}

AtomicDirectory::AtomicDirectory(fs::path path, bool force)
    : path_(std::move(path)), force_(force) {
  std::error_code ec;
  if (fs::exists(path_, ec) &&
      !(fs::is_directory(path_, ec) && fs::is_empty(path_, ec))) {
    RefuseToOverwrite(path_, force_, "output folder");
  }
  const fs::path parent =
      path_.parent_path().empty() ? fs::path(".") : path_.parent_path();
  if (!fs::is_directory(parent, ec)) {
    throw Error("parent folder does not exist", Location(parent.string()));
  }
  temp_path_ = TempPathBeside(path_);
  if (!fs::create_directory(temp_path_, ec)) {
    throw Error("cannot create output folder: " + ec.message(),
                Location(temp_path_.string()));
  }
}

AtomicDirectory::~AtomicDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_path_, ec);
  }
}

void AtomicDirectory::Commit() {
  std::error_code ec;
  if (fs::exists(path_, ec)) {
    // Either empty or --force: move the old folder aside first so that a failed
    // rename loses nothing.
    const fs::path old = TempPathBeside(path_);
    fs::rename(path_, old, ec);
    if (ec)
      throw Error("cannot replace: " + ec.message(), Location(path_.string()));
    fs::rename(temp_path_, path_, ec);
    if (ec) {
      fs::rename(old, path_);
      throw Error("cannot rename into place: " + ec.message(),
                  Location(path_.string()));
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(temp_path_, path_, ec);
    if (ec)
      throw Error("cannot rename into place: " + ec.message(),
                  Location(path_.string()));
  }
  committed_ = true;
}

std::string ReadFile(const fs::path& path) {
  RequireRegularFile(path, "file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(path.string()));
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw Error("read failed", Location(path.string()));
  return content.str();
}

}  // namespace lsds
