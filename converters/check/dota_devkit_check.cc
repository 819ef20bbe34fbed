// The DOTA devkit's parser (DOTA_devkit/dota_utils.py parse_dota_poly at
// 9938855), which ImgSplit.py and the DOTA evaluation read labels with.
#include <algorithm>
#include <system_error>

#include "converters/check/consumer.h"
#include "converters/check/dota_layout.h"
#include "converters/check/text_input.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace fs = std::filesystem;

const std::vector<Rule>& DotaDevkitRules() {
  static const std::vector<Rule> rules = {
      {"dota-devkit.header",
       Severity::kIgnored,
       "DOTA_devkit/dota_utils.py:61-66 (9938855)",
       "imagesource:/gsd: header lines have fewer than 9 tokens and are skipped, as intended"},
      {"dota-devkit.short-line",
       Severity::kDroppedBox,
       "DOTA_devkit/dota_utils.py:61-66 (9938855)",
       "a line of fewer than 9 single-space separated tokens is skipped (a tab-separated line "
       "is one token)"},
      {"dota-devkit.default-difficult",
       Severity::kIgnored,
       "DOTA_devkit/dota_utils.py:69-70 (9938855)",
       "a line of 9 tokens (no difficulty) is read as difficult 0"},
      {"dota-devkit.coordinates",
       Severity::kRejected,
       "DOTA_devkit/dota_utils.py:79-83 (9938855)",
       "a coordinate that float() refuses (also the empty token of two spaces in a row) "
       "stops parsing"},
  };
  return rules;
}

void CheckDotaDevkit(const std::string& /*format*/,
                     const fs::path& dir,
                     const CheckOptions& /*options*/,
                     FindingSink* sink) {
  std::error_code error;
  for (const DotaFolder& folder : DotaFolders(dir)) {
    std::vector<fs::path> annotations;
    for (const auto& entry : fs::directory_iterator(folder.labels, error)) {
      if (entry.is_regular_file(error) && entry.path().extension() == ".txt")
        annotations.push_back(entry.path());
    }
    std::sort(annotations.begin(), annotations.end());
    for (const fs::path& file : annotations) {
      sink->CountFile();
      std::string bytes;
      ReadBytes(file, &bytes);
      const std::vector<std::string> lines = SplitLines(bytes);
      for (size_t i = 0; i < lines.size(); ++i) {
        const int64_t line = static_cast<int64_t>(i) + 1;
        const std::string stripped = Strip(lines[i]);
        // line.strip().split(' '): single spaces only.
        const std::vector<std::string> tokens = Split(stripped, ' ');
        if (stripped.empty()) continue;  // the devkit skips it; nothing is lost
        if (tokens.size() < 9) {
          const bool header =
              stripped.rfind("imagesource:", 0) == 0 || stripped.rfind("gsd:", 0) == 0;
          sink->Add(header ? "dota-devkit.header" : "dota-devkit.short-line",
                    file,
                    line,
                    std::to_string(tokens.size()) + " token(s) split on single spaces: skipped");
          continue;
        }
        if (tokens.size() == 9) {
          sink->Add("dota-devkit.default-difficult", file, line, "no difficulty: read as 0");
        }
        for (size_t k = 0; k < 8; ++k) {
          double v = 0;
          if (!ParsePythonFloat(tokens[k], &v)) {
            sink->Add("dota-devkit.coordinates",
                      file,
                      line,
                      "coordinate '" + tokens[k] + "' is not a number: ValueError, parsing stops");
            break;
          }
        }
      }
    }
  }
}

}  // namespace lsds::check
