#include "tests/backproject/test_util.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>
#include "tests/build_paths.h"

namespace lsds::testing {

namespace fs = std::filesystem;

ScratchDir::ScratchDir(const std::string& name)
    : path_(fs::temp_directory_path() / ("lsds_bp_" + name + "_" + std::to_string(::getpid()))) {
  fs::remove_all(path_);
  fs::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

fs::path WriteSynth(const fs::path& root, const synth::Spec& spec) {
  synth::WriteCollection(root, spec);
  return root;
}

int RunLsds(const std::string& args, std::string* output) {
  const fs::path log = fs::temp_directory_path() / ("lsds_bp_log_" + std::to_string(::getpid()));
  const std::string command =
      ::lsds::testing::BinaryDir() + "/tools/lsds " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  if (output) *output = text.str();
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string ListDir(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  std::string joined;
  for (const auto& n : names) joined += n + " ";
  return joined;
}

}  // namespace lsds::testing
