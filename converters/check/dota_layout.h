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

// DIR/labelTxt, DIR/labelTxt/<split> (with DIR/images/<split>) and
// DIR/<split>/labelTxt, sorted.
std::vector<DotaFolder> DotaFolders(const std::filesystem::path& dir);

// The file lsds convert --to dota writes at the export root: the output class
// names, one a line, in the order to give MMRotate's `classes`.
inline constexpr const char* kDotaClassesFile = "dota_classes.txt";

// The names of DIR/dota_classes.txt; empty when there is none.
std::vector<std::string> DotaExportClasses(const std::filesystem::path& dir);

// The class names of DOTA v1.0 (MMRotate's DOTADataset.CLASSES, DOTA devkit's
// wordname_15).
const std::vector<std::string>& DotaV1Classes();

}  // namespace lsds::check
