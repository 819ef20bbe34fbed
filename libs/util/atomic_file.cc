#include "libs/util/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <system_error>

#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds {

namespace {

constexpr const char* kTempMarker = ".lsds-tmp-";

// This host's name, reduced to characters that are safe in a file name.
const std::string& HostName() {
  static const std::string name = [] {
    char buffer[256] = {};
    if (::gethostname(buffer, sizeof(buffer) - 1) != 0) return std::string("host");
    std::string safe;
    for (const char* c = buffer; *c != '\0' && safe.size() < 64; ++c)
      safe += std::isalnum(static_cast<unsigned char>(*c)) || *c == '.' ? *c : '_';
    return safe.empty() ? std::string("host") : safe;
  }();
  return name;
}

// Test hook for full-disk handling: with LSDS_FAULT_WRITE_BYTES=N in the
// environment, checked writes fail with ENOSPC once this process has written N
// bytes through them.
std::atomic<int64_t>& FaultBudget() {
  static std::atomic<int64_t> budget = [] {
    // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
    const char* value = std::getenv("LSDS_FAULT_WRITE_BYTES");
    return value == nullptr ? int64_t{-1} : std::atoll(value);
  }();
  return budget;
}

// Test hook for kills at the worst moment: with LSDS_FAULT_KILL_AFTER=NAME in
// the environment, the process kills itself (SIGKILL, no clean-up) right
// after a file named NAME is renamed into place.
void MaybeKillAfter(const fs::path& committed) {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
  static const char* const name = std::getenv("LSDS_FAULT_KILL_AFTER");
  if (name != nullptr && committed.filename() == name) ::raise(SIGKILL);
}

// std::strerror may share a buffer between threads; the category message does not.
std::string ErrnoText(int error) { return std::generic_category().message(error); }

// Makes a rename durable (best effort: not every file system can sync a
// folder).
void SyncFolder(const fs::path& folder) {
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Each folder is swept for stale temporaries once per process, when the first
// output goes into it.
void SweepOnce(const fs::path& folder) {
  static std::mutex mutex;
  static std::set<fs::path> swept;
  const fs::path key = folder.empty() ? fs::path(".") : folder;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (!swept.insert(key).second) return;
  }
  RemoveStaleTemps(key);
}

// A temporary's owner is gone: made on this host by a process that no longer
// exists.
bool OwnerGone(const std::string& file_name) {
  const size_t marker = file_name.rfind(kTempMarker);
  if (marker == std::string::npos) return false;
  const std::string rest = file_name.substr(marker + std::strlen(kTempMarker));
  const size_t last = rest.rfind('-');
  if (last == std::string::npos || last == 0) return false;
  const size_t before = rest.rfind('-', last - 1);
  if (before == std::string::npos) return false;
  const std::string host = rest.substr(0, before);
  const std::string pid_text = rest.substr(before + 1, last - before - 1);
  if (host != HostName() || pid_text.empty()) return false;
  char* end = nullptr;
  const long pid = std::strtol(pid_text.c_str(), &end, 10);
  if (*end != '\0' || pid <= 0) return false;
  if (pid == ::getpid()) return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

fs::path TempPathBeside(const fs::path& target) {
  static std::atomic<uint64_t> counter{0};
  // Keep the name within NAME_MAX for long targets.
  std::string stem = target.filename().string().substr(0, 120);
  std::ostringstream name;
  name << "." << stem << kTempMarker << HostName() << "-" << ::getpid() << "-" << counter++;
  return target.parent_path() / name.str();
}

bool IsTempName(const std::string& file_name) {
  return !file_name.empty() && file_name[0] == '.' &&
         file_name.find(kTempMarker) != std::string::npos;
}

size_t RemoveStaleTemps(const fs::path& folder, bool recursive) {
  size_t removed = 0;
  std::error_code ec;
  std::vector<fs::path> stale, below;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (IsTempName(name)) {
      if (OwnerGone(name)) stale.push_back(it->path());
    } else if (recursive && it->is_directory(ec) && !it->is_symlink(ec)) {
      below.push_back(it->path());
    }
  }
  for (const fs::path& path : stale) {
    std::error_code remove_ec;
    if (fs::remove_all(path, remove_ec) > 0) ++removed;
  }
  for (const fs::path& path : below) removed += RemoveStaleTemps(path, true);
  return removed;
}

void RefuseToOverwrite(const fs::path& path, bool force, const std::string& what) {
  std::error_code ec;
  if (!force && fs::exists(path, ec)) {
    throw Error(what + " exists; pass --force to overwrite it", Location(path.string()));
  }
}

void WriteFileAtomic(const fs::path& path, const std::string& content) {
  AtomicFile file(path);
  file.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  file.Commit();
}

void WriteFileAtomicVia(const fs::path& path,
                        const std::function<void(const fs::path& scratch)>& write) {
  const int memory = ::memfd_create("lsds-scratch", MFD_CLOEXEC);
  if (memory < 0) {
    throw Error("cannot create a scratch file: " + ErrnoText(errno), Location(path.string()));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{memory};
  write(fs::path("/proc/self/fd") / std::to_string(memory));
  AtomicFile file(path);
  std::vector<char> chunk(1 << 20);
  off_t offset = 0;
  while (true) {
    const ssize_t n = ::pread(memory, chunk.data(), chunk.size(), offset);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error("cannot read back the scratch file: " + ErrnoText(errno),
                  Location(path.string()));
    }
    if (n == 0) break;
    file.stream().write(chunk.data(), n);
    offset += n;
  }
  file.Commit();
}

// ---- CheckedFileBuf ----

CheckedFileBuf::CheckedFileBuf(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof(buffer_)); }

bool CheckedFileBuf::WriteAll(const char* data, size_t n) {
  if (error_ != 0) return false;
  std::atomic<int64_t>& budget = FaultBudget();
  while (n > 0) {
    // With the test hook on, each chunk reserves its bytes from the budget
    // first, so that writers on several threads never spend more than it
    // holds (the budget stays >= 0; -1 means no hook).
    size_t chunk = n;
    bool hooked = false;
    int64_t left = budget.load();
    while (left >= 0) {
      chunk = static_cast<size_t>(std::min<int64_t>(left, static_cast<int64_t>(n)));
      if (budget.compare_exchange_weak(left, left - static_cast<int64_t>(chunk))) {
        hooked = true;
        break;
      }
    }
    if (hooked && chunk == 0) {
      error_ = ENOSPC;
      return false;
    }
    const ssize_t written = ::write(fd_, data, chunk);
    if (hooked) budget += static_cast<int64_t>(chunk) - std::max<ssize_t>(written, 0);
    if (written < 0) {
      if (errno == EINTR) continue;
      error_ = errno;
      return false;
    }
    if (written == 0) {
      error_ = EIO;
      return false;
    }
    data += written;
    n -= static_cast<size_t>(written);
  }
  return true;
}

bool CheckedFileBuf::Flush() {
  const size_t pending = static_cast<size_t>(pptr() - pbase());
  const bool ok = WriteAll(pbase(), pending);
  setp(buffer_, buffer_ + sizeof(buffer_));
  return ok && error_ == 0;
}

CheckedFileBuf::int_type CheckedFileBuf::overflow(int_type c) {
  if (!Flush()) return traits_type::eof();
  if (!traits_type::eq_int_type(c, traits_type::eof())) {
    *pptr() = traits_type::to_char_type(c);
    pbump(1);
  }
  return traits_type::not_eof(c);
}

std::streamsize CheckedFileBuf::xsputn(const char* data, std::streamsize n) {
  if (n <= epptr() - pptr()) {
    std::memcpy(pptr(), data, static_cast<size_t>(n));
    pbump(static_cast<int>(n));
    return n;
  }
  if (!Flush() || !WriteAll(data, static_cast<size_t>(n))) return 0;
  return n;
}

int CheckedFileBuf::sync() { return Flush() ? 0 : -1; }

CheckedFileBuf::pos_type CheckedFileBuf::seekoff(off_type off,
                                                 std::ios_base::seekdir dir,
                                                 std::ios_base::openmode) {
  if (dir == std::ios_base::cur && off == 0) {  // tellp: no flush needed
    const off_t at = ::lseek(fd_, 0, SEEK_CUR);
    if (at < 0 || error_ != 0) return pos_type(off_type(-1));
    return pos_type(at + (pptr() - pbase()));
  }
  if (!Flush()) return pos_type(off_type(-1));
  const int whence = dir == std::ios_base::beg   ? SEEK_SET
                     : dir == std::ios_base::cur ? SEEK_CUR
                                                 : SEEK_END;
  const off_t at = ::lseek(fd_, off, whence);
  if (at < 0) {
    error_ = errno;
    return pos_type(off_type(-1));
  }
  return pos_type(at);
}

CheckedFileBuf::pos_type CheckedFileBuf::seekpos(pos_type pos, std::ios_base::openmode mode) {
  return seekoff(off_type(pos), std::ios_base::beg, mode);
}

// ---- AtomicFile ----

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)), temp_path_(TempPathBeside(path_)) {
  SweepOnce(path_.parent_path());
  fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd_ < 0) {
    throw Error("cannot open for writing: " + ErrnoText(errno), Location(path_.string()));
  }
  buffer_ = std::make_unique<CheckedFileBuf>(fd_);
  stream_ = std::make_unique<std::ostream>(buffer_.get());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    if (fd_ >= 0) ::close(fd_);
    std::error_code ec;
    fs::remove(temp_path_, ec);
  }
}

void AtomicFile::Fail(const std::string& what, int error) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  std::error_code ec;
  fs::remove(temp_path_, ec);
  throw Error(what + ": " + ErrnoText(error), Location(path_.string()));
}

void AtomicFile::Check() {
  if (fd_ < 0) {
    // A write that failed closed the file (Fail): a later check, such as
    // OpenEXR's writer flushing once more after the error, reports that
    // failure again rather than a misuse.
    if (!committed_) {
      const int error = buffer_->error() != 0 ? buffer_->error() : EIO;
      throw Error("cannot write (an earlier write failed): " + ErrnoText(error),
                  Location(path_.string()));
    }
    throw Error("already committed", Location(path_.string()));
  }
  buffer_->Flush();
  if (buffer_->error() != 0) Fail("cannot write", buffer_->error());
  if (!*stream_) Fail("cannot write", EIO);
}

void AtomicFile::Commit() {
  Check();
  // The data reaches the disk before the rename makes it visible: a power
  // loss then leaves either the old file or the whole new one.
  if (::fsync(fd_) != 0) Fail("cannot sync to disk", errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int error = errno;
    std::error_code ec;
    fs::remove(temp_path_, ec);
    throw Error("cannot close: " + ErrnoText(error), Location(path_.string()));
  }
  std::error_code ec;
  fs::rename(temp_path_, path_, ec);
  if (ec) {
    std::error_code remove_ec;
    fs::remove(temp_path_, remove_ec);
    throw Error("cannot rename into place: " + ec.message(), Location(path_.string()));
  }
  committed_ = true;
  SyncFolder(path_.parent_path());
  MaybeKillAfter(path_);
}

// ---- AtomicDirectory ----

AtomicDirectory::AtomicDirectory(fs::path path, bool force)
    : path_(std::move(path)), force_(force) {
  std::error_code ec;
  if (fs::exists(path_, ec) && !(fs::is_directory(path_, ec) && fs::is_empty(path_, ec))) {
    RefuseToOverwrite(path_, force_, "output folder");
  }
  const fs::path parent = path_.parent_path().empty() ? fs::path(".") : path_.parent_path();
  if (!fs::is_directory(parent, ec)) {
    throw Error("parent folder does not exist", Location(parent.string()));
  }
  SweepOnce(path_.parent_path());
  temp_path_ = TempPathBeside(path_);
  if (!fs::create_directory(temp_path_, ec)) {
    throw Error("cannot create output folder: " + ec.message(), Location(temp_path_.string()));
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
  // The files inside were synced by AtomicFile; their folder entries now.
  for (fs::recursive_directory_iterator it(temp_path_, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (it->is_directory(ec) && !it->is_symlink(ec)) SyncFolder(it->path());
  }
  SyncFolder(temp_path_);
  ec.clear();
  if (!force_) {
    // One rename, no look first: it replaces at most an empty folder, so when
    // another run wrote the same new output meanwhile, the later one fails
    // here instead of replacing the first one's folder.
    fs::rename(temp_path_, path_, ec);
    if (ec == std::errc::directory_not_empty || ec == std::errc::file_exists ||
        ec == std::errc::not_a_directory)
      throw Error(
          "the output was created by another run while this one was writing; nothing "
          "was replaced (pass --force to replace it)",
          Location(path_.string()));
    if (ec) throw Error("cannot rename into place: " + ec.message(), Location(path_.string()));
  } else if (fs::exists(path_, ec)) {
    // --force: move the old folder aside first so that a failed rename loses
    // nothing.
    const fs::path old = TempPathBeside(path_);
    fs::rename(path_, old, ec);
    if (ec) throw Error("cannot replace: " + ec.message(), Location(path_.string()));
    fs::rename(temp_path_, path_, ec);
    if (ec) {
      fs::rename(old, path_);
      throw Error("cannot rename into place: " + ec.message(), Location(path_.string()));
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(temp_path_, path_, ec);
    if (ec) throw Error("cannot rename into place: " + ec.message(), Location(path_.string()));
  }
  committed_ = true;
  SyncFolder(path_.parent_path());
}

// One buffer, sized as it is read, after the budget check: the one reader of
// whole files (ReadWholeFile, libs/util/input_file.h).
std::string ReadFile(const fs::path& path) { return ReadWholeFile(path, false); }

}  // namespace lsds
