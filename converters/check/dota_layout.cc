#include "converters/check/dota_layout.h"

#include <algorithm>
#include <system_error>

namespace lsds::check {

namespace fs = std::filesystem;

std::vector<DotaFolder> DotaFolders(const fs::path& dir) {
  std::vector<DotaFolder> folders;
  std::error_code error;
  if (fs::is_directory(dir / "labelTxt", error))
    folders.push_back({dir / "labelTxt", dir / "images"});
  std::vector<fs::path> splits;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (entry.is_directory(error) && fs::is_directory(entry.path() / "labelTxt", error))
      splits.push_back(entry.path());
  }
  std::sort(splits.begin(), splits.end());
  for (const fs::path& split : splits) folders.push_back({split / "labelTxt", split / "images"});
  return folders;
}

const std::vector<std::string>& DotaV1Classes() {
  // mmrotate/datasets/dota.py:33-36 (b030f38); DOTA_devkit/dota_utils.py:13-14.
  static const std::vector<std::string> classes = {"plane",
                                                   "baseball-diamond",
                                                   "bridge",
                                                   "ground-track-field",
                                                   "small-vehicle",
                                                   "large-vehicle",
                                                   "ship",
                                                   "tennis-court",
                                                   "basketball-court",
                                                   "storage-tank",
                                                   "soccer-ball-field",
                                                   "roundabout",
                                                   "harbor",
                                                   "swimming-pool",
                                                   "helicopter"};
  return classes;
}

}  // namespace lsds::check
