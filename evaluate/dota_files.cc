#include "evaluate/dota_files.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds::evaluate {

namespace fs = std::filesystem;

namespace {

// str.strip().split(' '): whitespace stripped at both ends, then every single
// space a separator (two spaces make an empty token).
std::vector<std::string> SplitOnSpace(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t\r\n\v\f");
  if (first == std::string::npos) return {""};
  const size_t last = line.find_last_not_of(" \t\r\n\v\f");
  const std::string stripped = line.substr(first, last - first + 1);
  std::vector<std::string> tokens;
  size_t start = 0;
  while (true) {
    const size_t space = stripped.find(' ', start);
    tokens.push_back(stripped.substr(start, space - start));
    if (space == std::string::npos) break;
    start = space + 1;
  }
  return tokens;
}

// Python's float() of a token: a finite decimal number (nan and inf refused).
double Number(const std::string& token, const std::string& file, size_t line, const char* what) {
  char* end = nullptr;
  const double value = token.empty() ? NAN : std::strtod(token.c_str(), &end);
  if (token.empty() || end != token.c_str() + token.size() || !std::isfinite(value))
    throw Error(std::string(what) + " is not a finite number: '" + token + "'",
                Location::Text(file, static_cast<int>(line), 0));
  return value;
}

template <typename Each>
void ForEachLine(const std::string& text, Each each) {
  std::istringstream in(text);
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) each(line, number);
}

}  // namespace

std::vector<DotaObject> ParseDotaLabels(const std::string& text,
                                        const std::string& file,
                                        const std::string& image) {
  std::vector<DotaObject> objects;
  ForEachLine(text, [&](const std::string& line, size_t number) {
    const std::vector<std::string> tokens = SplitOnSpace(line);
    if (tokens.size() < 9) return;  // parse_gt, task1.py:34-35
    DotaObject o;
    o.image = image;
    o.class_name = tokens[8];
    for (size_t i = 0; i < 8; ++i) o.quad[i] = Number(tokens[i], file, number, "a corner");
    o.difficult = tokens.size() == 10 && std::atoi(tokens[9].c_str()) != 0;
    objects.push_back(std::move(o));
  });
  return objects;
}

std::vector<DotaDetection> ReadDotaResults(const fs::path& folder,
                                           const std::vector<std::string>& class_names,
                                           const std::set<std::string>& images) {
  if (!fs::is_directory(folder))
    throw Error(
        "--format dota reads a folder of Task1_<class>.txt files (the DOTA devkit's detpath)",
        Location(folder.string()));
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("Task1_", 0) != 0 || entry.path().extension() != ".txt") continue;
    const std::string class_name = name.substr(6, name.size() - 6 - 4);
    if (std::find(class_names.begin(), class_names.end(), class_name) == class_names.end())
      throw Error("'" + class_name +
                      "' is not a class of the ground truth (as lsds convert --to dota names "
                      "them: dota_classes.txt)",
                  Location(entry.path().string()));
    files.push_back(entry.path());
  }
  if (files.empty())
    throw Error("no Task1_<class>.txt file in the folder", Location(folder.string()));
  std::sort(files.begin(), files.end());
  std::vector<DotaDetection> detections;
  for (const fs::path& path : files) {
    const std::string file = path.string();
    const std::string name = path.filename().string();
    const std::string class_name = name.substr(6, name.size() - 6 - 4);
    ForEachLine(ReadTextFile(path), [&](const std::string& line, size_t number) {
      const std::vector<std::string> tokens = SplitOnSpace(line);
      const Location at = Location::Text(file, static_cast<int>(number), 0);
      if (tokens.size() != 10)
        throw Error(
            "expected 'image score x1 y1 x2 y2 x3 y3 x4 y4' (10 fields split on single "
            "spaces), got " +
                std::to_string(tokens.size()),
            at);
      DotaDetection d;
      d.image = tokens[0];
      if (images.count(d.image) == 0)
        throw Error("image '" + d.image +
                        "' is not an image of the ground truth (the label file stem lsds convert "
                        "--to dota writes, 000007)",
                    at);
      d.class_name = class_name;
      d.score = Number(tokens[1], file, number, "the score");
      for (size_t i = 0; i < 8; ++i) d.quad[i] = Number(tokens[i + 2], file, number, "a corner");
      detections.push_back(std::move(d));
    });
  }
  return detections;
}

}  // namespace lsds::evaluate
