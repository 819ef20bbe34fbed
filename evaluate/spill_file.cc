#include "evaluate/spill_file.h"

#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

#include "libs/util/error.h"

namespace lsds::evaluate {

namespace {

std::string SystemError() { return std::generic_category().message(errno); }

}  // namespace

SpillFile::SpillFile() {
  std::string pattern =
      (std::filesystem::temp_directory_path() / "lsds-evaluate-spill-XXXXXX").string();
  fd_ = mkstemp(pattern.data());
  if (fd_ < 0)
    throw Error("cannot make a scratch file for what memory does not hold: " + SystemError() +
                    " (set TMPDIR to a folder with room, or raise --memory-budget)",
                Location(pattern));
  unlink(pattern.c_str());  // gone from the folder now; the space is freed with the descriptor
}

SpillFile::~SpillFile() {
  if (fd_ >= 0) close(fd_);
}

uint64_t SpillFile::Append(const void* bytes, size_t size) {
  const uint64_t offset = size_;
  const char* at = static_cast<const char*>(bytes);
  size_t left = size;
  while (left > 0) {
    const ssize_t n = pwrite(fd_, at, left, static_cast<off_t>(size_));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw Error("cannot write the scratch file in " +
                  std::filesystem::temp_directory_path().string() + ": " + SystemError() +
                  " (free space there, set TMPDIR to a folder with room, or raise "
                  "--memory-budget)");
    at += n;
    left -= static_cast<size_t>(n);
    size_ += static_cast<uint64_t>(n);
  }
  return offset;
}

void SpillFile::ReadAt(uint64_t offset, void* bytes, size_t size) const {
  char* at = static_cast<char*>(bytes);
  while (size > 0) {
    const ssize_t n = pread(fd_, at, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw Error("cannot read the scratch file back: " +
                  (n == 0 ? std::string("it is shorter than what was written") : SystemError()));
    at += n;
    size -= static_cast<size_t>(n);
    offset += static_cast<uint64_t>(n);
  }
}

SpillReader::SpillReader(const SpillFile& file, uint64_t offset, uint64_t end, size_t buffer_bytes)
    : file_(file), next_(offset), end_(end), capacity_(std::max<size_t>(buffer_bytes, 64)) {}

void SpillReader::Read(void* bytes, size_t size) {
  char* out = static_cast<char*>(bytes);
  while (size > 0) {
    if (at_ == buffer_.size()) {
      if (next_ == end_) throw Error("a run of the scratch file ends early");
      const size_t n = static_cast<size_t>(std::min<uint64_t>(capacity_, end_ - next_));
      buffer_.resize(n);
      file_.ReadAt(next_, buffer_.data(), n);
      next_ += n;
      at_ = 0;
    }
    const size_t n = std::min(size, buffer_.size() - at_);
    std::memcpy(out, buffer_.data() + at_, n);
    at_ += n;
    out += n;
    size -= n;
  }
}

size_t ReaderBufferBytes(uint64_t memory_bytes, size_t readers) {
  const uint64_t share = memory_bytes / std::max<size_t>(readers, 1);
  return static_cast<size_t>(std::clamp<uint64_t>(share, 4096, 1 << 20));
}

}  // namespace lsds::evaluate
