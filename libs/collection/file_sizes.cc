#include "libs/collection/file_sizes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <utility>

namespace lsds {

namespace {

// Folders kept open at once; a collection with more (a folder per frame)
// stats the rest by their whole path.
constexpr size_t kMaxOpenFolders = 64;

}  // namespace

FileSizes::FileSizes(std::filesystem::path root) : root_(std::move(root)) {}

FileSizes::~FileSizes() {
  for (const auto& [folder, fd] : folders_)
    if (fd >= 0) ::close(fd);
}

int FileSizes::Folder(const std::string& folder) {
  if (const auto it = folders_.find(folder); it != folders_.end()) return it->second;
  if (folders_.size() >= kMaxOpenFolders) return -1;
  const int fd = ::open((root_ / folder).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  folders_.emplace(folder, fd);
  return fd;
}

std::optional<uintmax_t> FileSizes::Size(const std::string& relative) {
  const size_t slash = relative.rfind('/');
  const int folder = slash == std::string::npos || relative.front() == '/'
                         ? -1
                         : Folder(relative.substr(0, slash));
  struct stat status {};
  const int result = folder >= 0 ? ::fstatat(folder, relative.c_str() + slash + 1, &status, 0)
                                 : ::stat((root_ / relative).c_str(), &status);
  if (result != 0 || !S_ISREG(status.st_mode)) return std::nullopt;
  return static_cast<uintmax_t>(status.st_size);
}

}  // namespace lsds
