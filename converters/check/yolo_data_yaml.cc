#include "converters/check/yolo_data_yaml.h"

#include "converters/check/text_input.h"

namespace lsds::check {

namespace {

// A scalar without its comment and quotes.
std::string Scalar(std::string text) {
  text = Strip(text);
  if (!text.empty() && (text[0] == '"' || text[0] == '\'')) {
    const size_t end = text.find(text[0], 1);
    return end == std::string::npos ? text.substr(1) : text.substr(1, end - 1);
  }
  const size_t comment = text.find(" #");
  if (comment != std::string::npos) text = text.substr(0, comment);
  if (!text.empty() && text[0] == '#') text.clear();
  return Strip(text);
}

// The items of a flow list or map: "[a, b]" or "{0: a, 1: b}".
std::vector<std::string> FlowItems(const std::string& text) {
  std::vector<std::string> items;
  std::string inner = Strip(text);
  inner = inner.substr(1, inner.size() >= 2 ? inner.size() - 2 : 0);
  std::string item;
  char quote = 0;
  for (char c : inner) {
    if (quote != 0) {
      if (c == quote) quote = 0;
      item += c;
    } else if (c == '"' || c == '\'') {
      quote = c;
      item += c;
    } else if (c == ',') {
      items.push_back(Scalar(item));
      item.clear();
    } else {
      item += c;
    }
  }
  if (!Strip(item).empty()) items.push_back(Scalar(item));
  return items;
}

}  // namespace

// One line-by-line parser loop (the YAML subset of a data.yaml).
// NOLINTNEXTLINE(readability-function-cognitive-complexity)
YoloDataYaml ReadYoloDataYaml(const std::filesystem::path& file) {
  YoloDataYaml data;
  data.root = file.parent_path();
  std::string bytes;
  if (!ReadBytes(file, &bytes)) {
    data.problem = "cannot read " + file.filename().string();
    return data;
  }
  std::string key;  // the top-level key whose block is being read
  std::optional<size_t> names, nc;
  size_t names_in_block = 0;
  for (const std::string& raw : SplitLines(bytes)) {
    const std::string line = Scalar(raw);
    if (line.empty()) continue;
    const bool indented = raw[0] == ' ' || raw[0] == '\t' || raw[0] == '-';
    if (indented && !key.empty()) {
      const std::string item = line[0] == '-' ? Scalar(line.substr(1)) : line;
      if (key == "names") {
        ++names_in_block;
      } else if (key == "train" || key == "val" || key == "test") {
        data.image_sources.push_back(item);
      }
      continue;
    }
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    if (key == "names") names = names_in_block;
    key = Strip(line.substr(0, colon));
    names_in_block = 0;
    const std::string value = Scalar(line.substr(colon + 1));
    if (key == "path" && !value.empty()) {
      const std::filesystem::path path(value);
      data.root = path.is_absolute() ? path : file.parent_path() / path;
    } else if (key == "train" || key == "val" || key == "test") {
      if (!value.empty() && value[0] == '[') {
        for (const std::string& item : FlowItems(value)) data.image_sources.push_back(item);
      } else if (!value.empty()) {
        data.image_sources.push_back(value);
      }
    } else if (key == "names" && !value.empty()) {
      names = FlowItems(value).size();
      key.clear();
    } else if (key == "nc") {
      long long count = 0;
      if (ParsePythonInt(value, &count) && count >= 0) nc = static_cast<size_t>(count);
    }
  }
  if (key == "names") names = names_in_block;
  data.class_count = names ? names : nc;
  if (!data.class_count) data.problem = "data.yaml has neither names nor nc";
  if (data.image_sources.empty()) data.problem = "data.yaml names no train, val or test images";
  return data;
}

}  // namespace lsds::check
