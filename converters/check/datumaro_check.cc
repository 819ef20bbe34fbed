// Datumaro's DOTA importer (src/datumaro/plugins/data_formats/dota.py at
// 3d533b9).
#include <algorithm>
#include <set>
#include <system_error>

#include "converters/check/consumer.h"
#include "converters/check/dota_layout.h"
#include "converters/check/text_input.h"

namespace lsds::check {

namespace fs = std::filesystem;

const std::vector<Rule>& DatumaroRules() {
  static const std::vector<Rule> rules = {
      {"datumaro.header",
       Severity::kIgnored,
       "src/datumaro/plugins/data_formats/dota.py:108-114 (3d533b9)",
       "imagesource:/gsd: header lines are skipped (not 10 tokens), as intended"},
      {"datumaro.tokens",
       Severity::kDroppedBox,
       "src/datumaro/plugins/data_formats/dota.py:108-114 (3d533b9)",
       "a line without exactly 10 tokens is skipped (logged at debug level only)"},
      {"datumaro.field",
       Severity::kRejected,
       "src/datumaro/plugins/data_formats/dota.py:123-130, 141-148 (3d533b9)",
       "a coordinate that is not a number or a difficulty that is not an integer: "
       "InvalidAnnotationError"},
      {"datumaro.image-missing",
       Severity::kRejected,
       "src/datumaro/plugins/data_formats/dota.py:59-63, 82-84 (3d533b9)",
       "every labelTxt file needs an image of the same stem under images/: KeyError otherwise"},
  };
  return rules;
}

namespace {

// The stems of the images under `images` (datumaro.util.image.IMAGE_EXTENSIONS,
// the common ones).
std::set<std::string> ImageStems(const fs::path& images) {
  static const std::set<std::string> kImageExtensions = {
      "jpg", "jpeg", "jpe", "jp2", "png", "bmp", "dib", "tif", "tiff", "tga", "webp",
      "pfm", "sr",   "ras", "exr", "hdr", "pic", "pbm", "pgm", "ppm",  "pxm", "pnm"};
  std::set<std::string> image_stems;
  for (const fs::path& image : ListFiles(images)) {
    if (kImageExtensions.count(LowerExtension(image)) > 0)
      image_stems.insert(image.stem().string());
  }
  return image_stems;
}

// One line of an annotation file as the importer reads it.
void CheckDotaLine(const std::string& text, const fs::path& file, int64_t line, FindingSink* sink) {
  const std::vector<std::string> tokens = SplitWhitespace(text);
  if (tokens.size() != 10) {
    const std::string stripped = Strip(text);
    const bool header = stripped.rfind("imagesource:", 0) == 0 || stripped.rfind("gsd:", 0) == 0;
    sink->Add(header ? "datumaro.header" : "datumaro.tokens",
              file,
              line,
              std::to_string(tokens.size()) + " token(s) (10 needed): skipped");
    return;
  }
  for (size_t k = 0; k < 8; ++k) {
    double v = 0;
    if (!ParsePythonFloat(tokens[k], &v)) {
      sink->Add("datumaro.field",
                file,
                line,
                "coordinate '" + tokens[k] + "' is not a number: the import fails");
      break;
    }
  }
  long long difficulty = 0;
  if (!ParsePythonInt(tokens[9], &difficulty)) {
    sink->Add("datumaro.field",
              file,
              line,
              "difficulty '" + tokens[9] + "' is not an integer: the import fails");
  }
}

// One annotation file and its image.
void CheckAnnotationFile(const fs::path& file,
                         const std::set<std::string>& image_stems,
                         FindingSink* sink) {
  sink->CountFile();
  if (image_stems.count(file.stem().string()) == 0) {
    sink->Add("datumaro.image-missing",
              file,
              0,
              "no image '" + file.stem().string() + ".*' under images/: the import fails");
  }
  std::string bytes;
  ReadBytes(file, &bytes);
  const std::vector<std::string> lines = SplitLines(bytes);
  for (size_t i = 0; i < lines.size(); ++i) {
    if (Strip(lines[i]).empty()) continue;
    CheckDotaLine(lines[i], file, static_cast<int64_t>(i) + 1, sink);
  }
}

}  // namespace

void CheckDatumaro(const std::string& /*format*/,
                   const fs::path& dir,
                   const CheckOptions& /*options*/,
                   FindingSink* sink) {
  std::error_code error;
  for (const DotaFolder& folder : DotaFolders(dir)) {
    const std::set<std::string> image_stems = ImageStems(folder.images);
    std::vector<fs::path> annotations;
    for (const auto& entry : fs::directory_iterator(folder.labels, error)) {
      if (entry.is_regular_file(error)) annotations.push_back(entry.path());
    }
    std::sort(annotations.begin(), annotations.end());
    for (const fs::path& file : annotations) CheckAnnotationFile(file, image_stems, sink);
  }
}

}  // namespace lsds::check
