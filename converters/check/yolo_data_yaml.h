// The keys of an Ultralytics data.yaml that decide what is loaded: the image
// folders of each split and the class names (their count is nc).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace lsds::check {

struct YoloDataYaml {
  std::filesystem::path root;              // `path:`, else the folder of data.yaml
  std::vector<std::string> image_sources;  // train, val, test values, as written
  std::optional<size_t> class_count;       // len(names), else nc
  std::string problem;                     // why the file cannot be used; empty when it can
};

// Reads the subset of YAML data.yaml files use: top-level `key: value`,
// `names:` as an indented map (`0: car`), a block list (`- car`) or a flow
// list (`[car, bus]`), and split values as a string or a list of strings.
YoloDataYaml ReadYoloDataYaml(const std::filesystem::path& file);

}  // namespace lsds::check
