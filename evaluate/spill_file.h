// A scratch file for what `lsds evaluate` does not keep in memory: sorted runs
// of records written once and read back in order (docs/evaluate.md, "Memory").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lsds::evaluate {

// An anonymous file in the system's temporary folder ($TMPDIR, else /tmp):
// made and unlinked at once, so that no path of exit (an error, a signal, a
// crash) leaves it behind; the space goes back when the object goes. Appends
// are serial; readers may read from any threads at once (pread).
class SpillFile {
 public:
  SpillFile();
  ~SpillFile();
  SpillFile(const SpillFile&) = delete;
  SpillFile& operator=(const SpillFile&) = delete;

  // Appends `size` bytes; returns the offset they start at. Throws lsds::Error
  // when the disk refuses them (full, quota).
  uint64_t Append(const void* bytes, size_t size);
  uint64_t size() const { return size_; }
  // Reads `size` bytes at `offset` (written before).
  void ReadAt(uint64_t offset, void* bytes, size_t size) const;

 private:
  int fd_ = -1;
  uint64_t size_ = 0;
};

// Reads a stretch of a SpillFile in order, through a buffer of its own.
class SpillReader {
 public:
  SpillReader(const SpillFile& file, uint64_t offset, uint64_t end, size_t buffer_bytes);
  bool done() const { return next_ == end_ && at_ == buffer_.size(); }
  // Throws lsds::Error past the end (a file shorter than what was written).
  void Read(void* bytes, size_t size);
  template <typename T>
  T Read() {
    T value;
    Read(&value, sizeof(T));
    return value;
  }

 private:
  const SpillFile& file_;
  uint64_t next_, end_;  // the stretch not yet buffered
  std::vector<char> buffer_;
  size_t at_ = 0;  // the next byte of buffer_
  size_t capacity_;
};

// What a reader's buffer may take when `readers` share `memory_bytes`:
// between 4 KiB and 1 MiB.
size_t ReaderBufferBytes(uint64_t memory_bytes, size_t readers);

}  // namespace lsds::evaluate
