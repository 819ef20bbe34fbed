#include "libs/util/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <system_error>
#include <thread>

#include "libs/util/error.h"

namespace lsds {

double LockTimeoutSeconds() {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
  const char* text = std::getenv("LSDS_LOCK_TIMEOUT");
  if (text == nullptr || *text == '\0') return 600;
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(seconds >= 0)) {
    throw Error("LSDS_LOCK_TIMEOUT: expected a number of seconds, got '" + std::string(text) + "'");
  }
  return seconds;
}

FolderLock::FolderLock(const std::filesystem::path& folder, const std::string& command) {
  fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) {
    throw Error("cannot open the folder to lock it: " + std::generic_category().message(errno),
                Location(folder.string()));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
  const double timeout = LockTimeoutSeconds();
  std::cerr << command << ": waiting for another lsds command writing to " << folder.string()
            << " (lock on the folder)\n";
  const auto start = std::chrono::steady_clock::now();
  while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (waited >= timeout) {
      ::close(fd_);
      fd_ = -1;
      throw Error(
          "another lsds command holds the write lock on this "
          "collection folder (waited " +
              std::to_string(static_cast<int>(waited)) + " s; LSDS_LOCK_TIMEOUT sets the wait)",
          Location(folder.string()));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the flock
}

}  // namespace lsds
