// MMRotate's DOTA loader (mmrotate/datasets/dota.py and
// mmrotate/core/bbox/transforms.py at b030f38, the 0.x line most DOTA
// configs use).
#include <algorithm>
#include <optional>
#include <system_error>

#include "converters/check/consumer.h"
#include "converters/check/dota_layout.h"
#include "converters/check/text_input.h"
#include "libs/geometry/oriented_box2d.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace fs = std::filesystem;

const std::vector<Rule>& MmrotateRules() {
  static const std::vector<Rule> rules = {
      {"mmrotate.no-annotations",
       Severity::kRejected,
       "mmrotate/datasets/dota.py:66-78 (b030f38)",
       "a labelTxt folder without .txt files is read as a test set: every image without boxes"},
      {"mmrotate.coordinates",
       Severity::kRejected,
       "mmrotate/datasets/dota.py:100 (b030f38)",
       "a line whose first 8 tokens are not all numbers (an imagesource:/gsd: header too) "
       "stops loading"},
      {"mmrotate.short-polygon",
       Severity::kDroppedBox,
       "mmrotate/datasets/dota.py:101-104 (b030f38)",
       "a line with fewer than 8 coordinates is skipped"},
      {"mmrotate.min-size",
       Severity::kDroppedBox,
       "mmrotate/core/bbox/transforms.py:347 (oc), 406 (le90) (b030f38)",
       "a box whose minimum-area rectangle has a side under 2 pixels is skipped"},
      {"mmrotate.tokens",
       Severity::kRejected,
       "mmrotate/datasets/dota.py:105-106 (b030f38)",
       "a line without class and difficulty (fewer than 10 tokens) stops loading"},
      {"mmrotate.difficulty",
       Severity::kRejected,
       "mmrotate/datasets/dota.py:106 (b030f38)",
       "a difficulty that is not an integer stops loading"},
      {"mmrotate.class",
       Severity::kRejected,
       "mmrotate/datasets/dota.py:63-65, 107 (b030f38)",
       "a class not among the configured classes (default: DOTA v1.0's 15) stops loading"},
      {"mmrotate.difficulty-threshold",
       Severity::kDroppedBox,
       "mmrotate/datasets/dota.py:47, 108-109 (b030f38)",
       "a box with difficulty above the threshold (default 100) is skipped"},
      {"mmrotate.empty-image",
       Severity::kDroppedImage,
       "mmrotate/datasets/dota.py:93-94, 149-156 (b030f38)",
       "an image with no box kept is filtered out of training (filter_empty_gt)"},
      {"mmrotate.image-missing",
       Severity::kRejected,
       "mmrotate/datasets/dota.py:82-84 (b030f38)",
       "the image of labelTxt/<stem>.txt is images/<stem>.png; a missing one stops loading"},
  };
  return rules;
}

namespace {

// The .txt files of a labelTxt folder, sorted.
std::vector<fs::path> AnnotationFiles(const fs::path& labels) {
  std::error_code error;
  std::vector<fs::path> annotations;
  for (const auto& entry : fs::directory_iterator(labels, error)) {
    if (entry.is_regular_file(error) && entry.path().extension() == ".txt")
      annotations.push_back(entry.path());
  }
  std::sort(annotations.begin(), annotations.end());
  return annotations;
}

// The polygon of a line's first 8 tokens; false when one is not a number.
bool ParsePolygon(const std::vector<std::string>& tokens, std::vector<Eigen::Vector2d>* points) {
  bool numeric = true;
  for (size_t k = 0; k < std::min<size_t>(8, tokens.size()); ++k) {
    double v = 0;
    numeric = numeric && ParsePythonFloat(tokens[k], &v);
    if (k % 2 == 0)
      points->emplace_back(v, 0);
    else
      points->back().y() = v;
  }
  return numeric;
}

// One line of an annotation file as DOTADataset.load_annotations reads it;
// true when its box is kept.
bool CheckDotaLine(const std::vector<std::string>& tokens,
                   const std::vector<std::string>& classes,
                   const fs::path& file,
                   int64_t line,
                   FindingSink* sink) {
  std::vector<Eigen::Vector2d> points;
  if (!ParsePolygon(tokens, &points)) {
    sink->Add("mmrotate.coordinates",
              file,
              line,
              "'" +
                  Join(std::vector<std::string>(
                           tokens.begin(), tokens.begin() + std::min<size_t>(3, tokens.size())),
                       " ") +
                  "...' is not 8 numbers: ValueError, loading stops");
    return false;
  }
  if (tokens.size() < 8) {
    sink->Add("mmrotate.short-polygon",
              file,
              line,
              std::to_string(tokens.size()) + " coordinate(s) (8 needed): skipped");
    return false;
  }
  // cv2.minAreaRect of the 4 corners, then w < 2 or h < 2 is skipped.
  const std::optional<OrientedBox2d> box = MinimumAreaRectangle(points);
  const double w = box ? box->Width() : 0, h = box ? box->Height() : 0;
  if (w < 2 || h < 2) {
    sink->Add("mmrotate.min-size",
              file,
              line,
              "minimum-area rectangle " + FormatNumber(w, 4) + " x " + FormatNumber(h, 4) +
                  " px (a side under 2): skipped");
    return false;
  }
  if (tokens.size() < 10) {
    sink->Add("mmrotate.tokens",
              file,
              line,
              std::to_string(tokens.size()) + " token(s) (10 needed): IndexError, loading stops");
    return false;
  }
  long long difficulty = 0;
  if (!ParsePythonInt(tokens[9], &difficulty)) {
    sink->Add("mmrotate.difficulty",
              file,
              line,
              "difficulty '" + tokens[9] + "' is not an integer: loading stops");
    return false;
  }
  if (std::find(classes.begin(), classes.end(), tokens[8]) == classes.end()) {
    sink->Add("mmrotate.class",
              file,
              line,
              "class '" + tokens[8] + "' is not configured (classes=): KeyError, loading stops");
    return false;
  }
  if (difficulty > 100) {
    sink->Add("mmrotate.difficulty-threshold",
              file,
              line,
              "difficulty " + tokens[9] + " above the default threshold 100: skipped");
    return false;
  }
  return true;
}

// One annotation file and its image.
void CheckAnnotationFile(const fs::path& file,
                         const DotaFolder& folder,
                         const fs::path& dir,
                         const std::vector<std::string>& classes,
                         FindingSink* sink) {
  std::error_code error;
  sink->CountFile();
  const fs::path image = folder.images / (file.stem().string() + ".png");
  if (!fs::is_regular_file(image, error)) {
    sink->Add("mmrotate.image-missing",
              file,
              0,
              "no image " + fs::relative(image, dir, error).string() + ": loading it fails");
  }
  std::string bytes;
  ReadBytes(file, &bytes);
  int kept = 0;
  const std::vector<std::string> lines = SplitLines(bytes);
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::vector<std::string> tokens = SplitWhitespace(lines[i]);
    if (tokens.empty()) continue;  // an empty polygon: skipped, nothing lost
    if (CheckDotaLine(tokens, classes, file, static_cast<int64_t>(i) + 1, sink)) ++kept;
  }
  if (kept == 0) {
    sink->Add("mmrotate.empty-image",
              file,
              0,
              bytes.empty() ? "empty annotation file: the image is skipped"
                            : "no box kept: the image is filtered out of training");
  }
}

}  // namespace

void CheckMmrotate(const std::string& /*format*/,
                   const fs::path& dir,
                   const CheckOptions& options,
                   FindingSink* sink) {
  // The classes the user configures MMRotate with: given, else those the
  // export lists, else MMRotate's default (DOTA v1.0).
  std::vector<std::string> classes = options.dota_classes;
  if (classes.empty()) classes = DotaExportClasses(dir);
  if (classes.empty()) classes = DotaV1Classes();
  for (const DotaFolder& folder : DotaFolders(dir)) {
    const std::vector<fs::path> annotations = AnnotationFiles(folder.labels);
    if (annotations.empty()) {
      sink->Add("mmrotate.no-annotations",
                folder.labels,
                0,
                "no .txt file: read as a test set, without boxes");
      continue;
    }
    for (const fs::path& file : annotations) CheckAnnotationFile(file, folder, dir, classes, sink);
  }
}

}  // namespace lsds::check
