// Ultralytics' loading rules for YOLO detect, segment and OBB labels, ported
// from verify_image_label (ultralytics/data/utils.py at 00bfe34) and its
// caller YOLODataset (ultralytics/data/dataset.py at 0088d78).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "converters/check/consumer.h"
#include "converters/check/text_input.h"
#include "converters/check/yolo_data_yaml.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace fs = std::filesystem;

const std::vector<Rule>& UltralyticsRules() {
  static const std::vector<Rule> rules = {
      {"ultralytics.data-yaml",
       Severity::kRejected,
       "ultralytics/data/dataset.py:118 (0088d78)",
       "data.yaml must exist and name the classes (nc = len(names)) and the image folders"},
      {"ultralytics.no-images",
       Severity::kRejected,
       "ultralytics/data/dataset.py:187-190 (0088d78)",
       "no image of a split survives the checks: 'No valid images found'"},
      {"ultralytics.image-corrupt",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:188-189, 246-248 (00bfe34)",
       "the image cannot be decoded: the image and its labels are ignored"},
      {"ultralytics.image-too-small",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:192 (00bfe34)",
       "an image side under 10 pixels"},
      {"ultralytics.label-unreadable",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:204-205, 246-248 (00bfe34)",
       "the label file cannot be read as UTF-8 text"},
      {"ultralytics.label-not-numeric",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:207-210 (00bfe34)",
       "a label row holds a token that is not a number, or no token at all"},
      {"ultralytics.label-columns",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:206-208, 216 (00bfe34)",
       "box rows need 5 columns; segment rows (any row over 6 columns makes every row a "
       "segment) need an even, non-zero number of coordinates"},
      {"ultralytics.coordinate-range",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:219-220 (00bfe34)",
       "a box (x, y, w, h; of a segment, its bounding box) above 1.01 or a value below -0.01"},
      {"ultralytics.class-range",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:223-227 (00bfe34); dataset.py:118 (0088d78)",
       "a class index >= nc, the number of names in data.yaml"},
      {"ultralytics.duplicate-row",
       Severity::kDroppedBox,
       "ultralytics/data/utils.py:228-233 (00bfe34)",
       "a row equal to an earlier one (of a segment: equal bounding box) is removed"},
      {"ultralytics.segment-points",
       Severity::kDroppedBox,
       "ultralytics/data/utils.py:206-209 (00bfe34)",
       "a segment of fewer than 3 points has no area: its mask is empty"},
      {"ultralytics.segments-removed",
       Severity::kRejected,
       "ultralytics/data/dataset.py:196-203 (0088d78)",
       "a yolo-seg label file whose rows all have 6 columns or fewer is read as boxes; "
       "then boxes and segments differ in number and every segment of the dataset is removed"},
      {"ultralytics.label-without-image",
       Severity::kDroppedImage,
       "ultralytics/data/utils.py:45-48 (00bfe34)",
       "a label file no listed image maps to (images/ -> labels/, extension -> .txt) is never "
       "read"},
  };
  return rules;
}

namespace {

// IMG_FORMATS, ultralytics/data/utils.py:40 (00bfe34).
const std::set<std::string>& ImageFormats() {
  static const std::set<std::string> formats = {
      "bmp", "dng", "jpeg", "jpg", "mpo", "png", "tif", "tiff", "webp", "pfm", "heic"};
  return formats;
}

// img2label_paths: the last "/images/" becomes "/labels/", the extension ".txt".
fs::path LabelPathOf(const fs::path& image) {
  std::string text = image.string();
  const size_t at = text.rfind("/images/");
  if (at != std::string::npos) text.replace(at, 8, "/labels/");
  const size_t dot = text.rfind('.');
  const size_t slash = text.rfind('/');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash))
    text = text.substr(0, dot);
  return fs::path(text + ".txt");
}

// The images of one split value: a folder (searched recursively) or a .txt
// list of image paths.
std::vector<fs::path> SplitImages(const fs::path& root, const std::string& source, bool* found) {
  const fs::path path = fs::path(source).is_absolute() ? fs::path(source) : root / source;
  std::vector<fs::path> images;
  std::error_code error;
  *found = fs::exists(path, error);
  if (fs::is_directory(path, error)) {
    for (const fs::path& file : ListFiles(path)) {
      if (ImageFormats().count(LowerExtension(file)) > 0) images.push_back(file);
    }
  } else if (fs::is_regular_file(path, error)) {
    std::string bytes;
    if (ReadBytes(path, &bytes)) {
      for (const std::string& line : SplitLines(bytes)) {
        const std::string name = Strip(line);
        if (name.empty()) continue;
        const fs::path image = fs::path(name).is_absolute() ? fs::path(name) : root / name;
        if (ImageFormats().count(LowerExtension(image)) > 0) images.push_back(image);
      }
    }
  }
  return images;
}

bool ValidUtf8(const std::string& text) {
  size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    const size_t n = c < 0x80           ? 1
                     : (c >> 5) == 0x6  ? 2
                     : (c >> 4) == 0xE  ? 3
                     : (c >> 3) == 0x1E ? 4
                                        : 0;
    if (n == 0 || i + n > text.size()) return false;
    for (size_t k = 1; k < n; ++k) {
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
    }
    i += n;
  }
  return true;
}

// One label row as verify_image_label holds it: class and box (x, y, w, h),
// float32 as numpy holds them.
struct Row {
  int64_t line = 0;
  std::array<float, 5> values{};
  size_t points = 0;  // segment points (0 for a box row)
};

// A line of a label file and its whitespace-separated tokens.
using TokenRow = std::pair<int64_t, std::vector<std::string>>;

// f.read().strip().splitlines() keeping the lines with any character: a
// line of spaces inside the file becomes a row without tokens.
std::vector<TokenRow> TokenRows(const std::string& bytes) {
  std::vector<TokenRow> rows;
  const std::vector<std::string> lines = SplitLines(bytes);
  size_t first = 0, last = lines.size();
  while (first < last && Strip(lines[first]).empty()) ++first;
  while (last > first && Strip(lines[last - 1]).empty()) --last;
  for (size_t i = first; i < last; ++i) {
    if (lines[i].empty()) continue;
    rows.emplace_back(static_cast<int64_t>(i) + 1, SplitWhitespace(lines[i]));
  }
  return rows;
}

// The row's tokens as numbers; false when one is not a number, or there are
// none.
bool ParseNumbers(const std::vector<std::string>& tokens, std::vector<double>* numbers) {
  for (const std::string& token : tokens) {
    double v = 0;
    if (!ParsePythonFloat(token, &v)) return false;
    numbers->push_back(v);
  }
  return !tokens.empty();
}

// segments2boxes: the bounding box of a segment row's points, as x, y, w, h;
// false when its coordinates do not pair into points.
bool ParseSegmentRow(const std::vector<double>& numbers,
                     const fs::path& label_file,
                     FindingSink* sink,
                     Row* row) {
  const size_t coordinates = numbers.size() - 1;
  if (coordinates == 0 || coordinates % 2 != 0) {
    sink->Add("ultralytics.label-columns",
              label_file,
              row->line,
              std::to_string(coordinates) +
                  " coordinate(s) in a segment file: they do not pair into points; "
                  "the image is ignored");
    return false;
  }
  float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (size_t i = 1; i + 1 < numbers.size(); i += 2) {
    const auto x = static_cast<float>(numbers[i]), y = static_cast<float>(numbers[i + 1]);
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  row->values = {row->values[0], (x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0};
  row->points = coordinates / 2;
  return true;
}

// One row as verify_image_label parses it (a box row of the file's first
// row's width, or a segment); false when the image is dropped for it.
bool ParseRow(const TokenRow& token_row,
              bool segment_file,
              size_t width,
              const fs::path& label_file,
              FindingSink* sink,
              Row* row) {
  const auto& [line, tokens] = token_row;
  std::vector<double> numbers;
  if (!ParseNumbers(tokens, &numbers)) {
    sink->Add("ultralytics.label-not-numeric",
              label_file,
              line,
              tokens.empty() ? "a row without tokens (a line of spaces)"
                             : "a token is not a number: the image is ignored");
    return false;
  }
  row->line = line;
  row->values[0] = static_cast<float>(numbers[0]);
  if (segment_file) return ParseSegmentRow(numbers, label_file, sink, row);
  if (numbers.size() != 5 || tokens.size() != width) {
    sink->Add("ultralytics.label-columns",
              label_file,
              line,
              "labels require 5 columns, " + std::to_string(numbers.size()) +
                  " found: the image is ignored");
    return false;
  }
  for (size_t i = 1; i < 5; ++i) row->values[i] = static_cast<float>(numbers[i]);
  return true;
}

// The coordinate and class ranges of a parsed row; false when the image is
// dropped for it. The comparisons are those of numpy on float32 arrays: NaN
// fails both.
bool CheckRowRanges(const Row& row,
                    size_t class_count,
                    const fs::path& label_file,
                    FindingSink* sink) {
  bool kept = true;
  for (size_t i = 1; i < 5; ++i) {
    if (!(row.values[i] <= 1.01f)) {
      sink->Add("ultralytics.coordinate-range",
                label_file,
                row.line,
                std::string(row.points > 0 ? "bounding box of the segment: " : "") + "value " +
                    FormatNumber(row.values[i]) +
                    " above 1.01 (non-normalized or out of bounds): the image is ignored");
      kept = false;
      break;
    }
  }
  for (size_t i = 0; i < 5; ++i) {
    if (!(row.values[i] >= -0.01f)) {
      sink->Add("ultralytics.coordinate-range",
                label_file,
                row.line,
                std::string(i == 0 ? "class" : "value") + " " + FormatNumber(row.values[i]) +
                    " below -0.01: the image is ignored");
      kept = false;
      break;
    }
  }
  if (!(row.values[0] < static_cast<float>(class_count))) {
    sink->Add("ultralytics.class-range",
              label_file,
              row.line,
              "class " + FormatNumber(row.values[0]) + " >= nc " + std::to_string(class_count) +
                  " (the names of data.yaml): the image is ignored");
    kept = false;
  }
  return kept;
}

// What a kept image loses: duplicate rows, segments without area.
void CheckKeptRows(const std::vector<Row>& parsed,
                   const std::string& format,
                   const fs::path& label_file,
                   FindingSink* sink) {
  std::map<std::array<float, 5>, int64_t> first_line;
  for (const Row& row : parsed) {
    const auto [it, inserted] = first_line.emplace(row.values, row.line);
    if (!inserted) {
      sink->Add("ultralytics.duplicate-row",
                label_file,
                row.line,
                "equal to line " + std::to_string(it->second) +
                    (row.points > 0 ? " (as a bounding box)" : "") + ": removed");
    }
    if (format == "yolo-seg" && row.points > 0 && row.points < 3) {
      sink->Add("ultralytics.segment-points",
                label_file,
                row.line,
                std::to_string(row.points) + " point(s): the segment has no area");
    }
  }
}

// Checks one image's label file; returns false when the image is dropped.
bool CheckLabelFile(const fs::path& label_file,
                    const std::string& format,
                    size_t class_count,
                    FindingSink* sink) {
  std::string bytes;
  if (!ReadBytes(label_file, &bytes) || !ValidUtf8(bytes)) {
    sink->Add("ultralytics.label-unreadable", label_file, 0, "not readable as UTF-8 text");
    return false;
  }
  sink->CountFile();
  const std::vector<TokenRow> rows = TokenRows(bytes);
  if (rows.empty()) return true;  // a background image
  const bool segment_file =
      std::any_of(rows.begin(), rows.end(), [](const auto& row) { return row.second.size() > 6; });
  bool dropped = false;
  std::vector<Row> parsed;
  const size_t width = rows.front().second.size();
  for (const TokenRow& token_row : rows) {
    Row row;
    if (ParseRow(token_row, segment_file, width, label_file, sink, &row)) {
      parsed.push_back(row);
    } else {
      dropped = true;
    }
  }
  for (const Row& row : parsed) {
    if (!CheckRowRanges(row, class_count, label_file, sink)) dropped = true;
  }
  if (dropped) return false;
  CheckKeptRows(parsed, format, label_file, sink);
  if (format == "yolo-seg" && !segment_file) {
    sink->Add("ultralytics.segments-removed",
              label_file,
              rows.front().first,
              "no row has more than 6 columns: read as boxes, so Ultralytics removes every "
              "segment of the dataset");
  }
  return true;
}

}  // namespace

void CheckUltralytics(const std::string& format,
                      const fs::path& dir,
                      const CheckOptions& /*options*/,
                      FindingSink* sink) {
  const fs::path yaml = dir / "data.yaml";
  std::error_code error;
  if (!fs::is_regular_file(yaml, error)) {
    sink->Add("ultralytics.data-yaml", yaml, 0, "no data.yaml in the export folder");
    return;
  }
  const YoloDataYaml data = ReadYoloDataYaml(yaml);
  sink->CountFile();
  if (!data.problem.empty()) {
    sink->Add("ultralytics.data-yaml", yaml, 0, data.problem);
    return;
  }
  std::set<fs::path> label_files_read;
  std::set<fs::path> sources_seen;
  for (const std::string& source : data.image_sources) {
    bool found = false;
    const std::vector<fs::path> images = SplitImages(data.root, source, &found);
    const fs::path where = fs::weakly_canonical(data.root / source, error);
    if (!sources_seen.insert(where).second) continue;  // val given as train: read once here
    if (!found) {
      sink->Add("ultralytics.data-yaml", yaml, 0, "image source '" + source + "' does not exist");
      continue;
    }
    size_t kept = 0;
    for (const fs::path& image : images) {
      int width = 0, height = 0;
      sink->CountFile();
      if (!DecodeImageSize(image, &width, &height)) {
        sink->Add(
            "ultralytics.image-corrupt", image, 0, "cannot be decoded: ignored with its labels");
        continue;
      }
      if (width <= 9 || height <= 9) {
        sink->Add("ultralytics.image-too-small",
                  image,
                  0,
                  std::to_string(width) + "x" + std::to_string(height) +
                      " pixels (under 10): ignored with its labels");
        continue;
      }
      const fs::path label = LabelPathOf(image);
      label_files_read.insert(fs::weakly_canonical(label, error));
      if (fs::is_regular_file(label, error) &&
          !CheckLabelFile(label, format, *data.class_count, sink))
        continue;
      ++kept;
    }
    if (kept == 0) {
      sink->Add("ultralytics.no-images",
                yaml,
                0,
                "no valid image in '" + source + "' (" + std::to_string(images.size()) +
                    " listed): training stops");
    }
  }
  for (const fs::path& label : ListFiles(data.root / "labels")) {
    if (LowerExtension(label) != "txt") continue;
    if (label_files_read.count(fs::weakly_canonical(label, error)) == 0) {
      sink->Add("ultralytics.label-without-image",
                label,
                0,
                "no image of data.yaml's splits maps to this label file: never read");
    }
  }
}

}  // namespace lsds::check
