// Writers of one collection take turns: an exclusive flock(2) on the
// collection folder itself (no lock file is left in the collection). A second
// writer waits for the first (up to LSDS_LOCK_TIMEOUT seconds, default 600),
// then fails naming the folder; readers take no lock.
#pragma once

#include <filesystem>
#include <string>

namespace lsds {

class FolderLock {
 public:
  // Blocks until the lock is held; throws lsds::Error (exit 2) naming the
  // folder when it cannot be opened or the wait times out. `command` is said
  // in the waiting note.
  FolderLock(const std::filesystem::path& folder, const std::string& command);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// Seconds a writer waits for the lock: LSDS_LOCK_TIMEOUT, default 600.
double LockTimeoutSeconds();

}  // namespace lsds
