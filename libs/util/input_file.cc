#include "libs/util/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>
#include <vector>

#include "libs/util/error.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds {

namespace fs = std::filesystem;

void RequireRegularFile(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || status.type() == fs::file_type::not_found) {
    throw Error("cannot read the " + what + ": it does not exist", Location(path.string()));
  }
  if (status.type() == fs::file_type::directory) {
    throw Error("the " + what + " is a folder, expected a file", Location(path.string()));
  }
  if (status.type() != fs::file_type::regular) {
    throw Error("the " + what +
                    " is not a regular file (a FIFO, socket or device); lsds "
                    "reads only regular files",
                Location(path.string()));
  }
}

// The one reader of whole files. Appends in chunks of at most 1 MiB straight
// into the result (no stream buffer and no copy of the whole), after the size
// the file has now is checked against the memory budget; a file that grows
// while it is read is read to its end all the same.
std::string ReadWholeFile(const fs::path& path, bool text) {
  RequireRegularFile(path, "file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    throw Error("cannot open for reading: " + std::system_category().message(errno),
                Location(path.string()));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw Error("cannot read: " + std::system_category().message(errno), Location(path.string()));
  const auto size = static_cast<uint64_t>(std::max<off_t>(st.st_size, 0));
  CheckMemoryBudget(static_cast<double>(size), "reading the whole file", path.string());
  std::string content;
  // Only reserved: a page is touched when its bytes arrive, so a text file
  // refused at its first NUL costs its first chunk, whatever its size.
  content.reserve(static_cast<size_t>(size));
  constexpr size_t kChunk = size_t{1} << 20;
  char more[4096];  // past the reserved size: a file that grew, or the end
  for (;;) {
    const size_t old = content.size();
    const size_t room = content.capacity() - old;
    ssize_t got = 0;
    if (room > 0) {
      const size_t want = std::min(kChunk, room);
      content.resize(old + want);
      got = ::read(fd, content.data() + old, want);
      content.resize(old + static_cast<size_t>(std::max<ssize_t>(got, 0)));
    } else {
      got = ::read(fd, more, sizeof more);
      if (got > 0) content.append(more, static_cast<size_t>(got));
    }
    if (got < 0) {
      if (errno == EINTR) continue;
      throw Error("read failed: " + std::system_category().message(errno), Location(path.string()));
    }
    if (got == 0) break;
    if (text && std::memchr(content.data() + old, '\0', static_cast<size_t>(got)) != nullptr)
      CheckNoNulBytes(content, path.string());  // throws, at the NUL's line:column
    if (content.size() > size) {
      CheckMemoryBudget(
          static_cast<double>(content.size()), "reading the whole file", path.string());
    }
  }
  return content;
}

std::string ReadTextFile(const fs::path& path) { return ReadWholeFile(path, true); }

Location TextLocationInFile(const fs::path& path, uint64_t offset) {
  Location where = Location::Text(path.string(), 1, 1);
  std::ifstream in(path, std::ios::binary);
  std::vector<char> chunk(1 << 16);
  uint64_t at = 0;
  while (at < offset && in) {
    in.read(chunk.data(),
            static_cast<std::streamsize>(std::min<uint64_t>(chunk.size(), offset - at)));
    const auto got = static_cast<size_t>(in.gcount());
    for (size_t k = 0; k < got; ++k) {
      if (chunk[k] == '\n') {
        ++where.line;
        where.column = 1;
      } else {
        ++where.column;
      }
    }
    at += got;
    if (got == 0) break;
  }
  return where;
}

}  // namespace lsds
