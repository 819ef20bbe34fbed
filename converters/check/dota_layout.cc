#include "converters/check/dota_layout.h"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace lsds::check {

namespace fs = std::filesystem;

std::vector<DotaFolder> DotaFolders(const fs::path& dir) {
  std::vector<DotaFolder> folders;
  std::error_code error;
  if (fs::is_directory(dir / "labelTxt", error)) {
    // lsds convert's layout, as MMRotate's configs name it
    // (ann_file='labelTxt/train/', img_prefix='images/train/'): one folder per
    // split inside labelTxt/ and images/.
    std::vector<fs::path> inner;
    bool files = false;
    for (const auto& entry : fs::directory_iterator(dir / "labelTxt", error)) {
      if (entry.is_directory(error)) inner.push_back(entry.path().filename());
      if (entry.is_regular_file(error)) files = true;
    }
    std::sort(inner.begin(), inner.end());
    if (files || inner.empty()) folders.push_back({dir / "labelTxt", dir / "images"});
    for (const fs::path& split : inner)
      folders.push_back({dir / "labelTxt" / split, dir / "images" / split});
  }
  std::vector<fs::path> splits;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (entry.is_directory(error) && fs::is_directory(entry.path() / "labelTxt", error))
      splits.push_back(entry.path());
  }
  std::sort(splits.begin(), splits.end());
  for (const fs::path& split : splits) folders.push_back({split / "labelTxt", split / "images"});
  return folders;
}

std::vector<std::string> DotaExportClasses(const fs::path& dir) {
  std::vector<std::string> classes;
  std::ifstream in(dir / kDotaClassesFile);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) classes.push_back(line);
  }
  return classes;
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
