// Where a DOTA export keeps its files: labelTxt/<stem>.txt beside images/,
// at the top of the export folder or in one folder per split.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lsds::check {

struct DotaFolder {
  std::filesystem::path labels;  // .../labelTxt
  std::filesystem::path images;  // .../images (may be missing)
};

// DIR/labelTxt and DIR/<split>/labelTxt, sorted.
std::vector<DotaFolder> DotaFolders(const std::filesystem::path& dir);

// The class names of DOTA v1.0 (MMRotate's DOTADataset.CLASSES, DOTA devkit's
// wordname_15).
const std::vector<std::string>& DotaV1Classes();

}  // namespace lsds::check
