// Every example scene and capture plans to the
// same bytes, or is refused with the same message, as recorded in plan_goldens.txt: a digest of
// `lsds plan`'s JSON per (scene, capture, seed). A change meant to keep plans (a refactor of the
// evaluators) must leave every digest; a change meant to alter them (a defect fix) updates the file
// with LSDS_UPDATE_GOLDEN=1 and shows in its diff which inputs it touched.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "generator/estimate.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"

namespace lsds {
namespace {

struct Input {
  std::string scene;    // relative to the repository root
  std::string capture;  // "" for the default capture
  uint64_t seed;
};

const Input kInputs[] = {
    {"examples/checkpoint_relations.lscene", "examples/checkpoint_relations.lcap", 1},
    {"examples/field_day.lscene", "examples/field_day.lcap", 1},
    {"examples/paper_example1.lscene", "examples/paper_example1.lcap", 1},
    {"examples/paper_example1_verbatim.lscene", "examples/paper_example1_verbatim.lcap", 1},
    {"examples/time_of_day_movers.lscene", "examples/time_of_day_movers.lcap", 1},
    {"examples/uav_survey.lscene", "examples/uav_survey.lcap", 1},
    {"examples/uav_survey.lscene", "examples/demo_survey.lcap", 1},
    {"examples/rocky_sand_clutter.lscene", "examples/rocky_sand_random.lcap", 1},
    {"examples/rocky_sand_clutter.lscene", "examples/rocky_sand_random.lcap", 2},
    {"examples/field_day.lscene", "", 1},
    {"examples/rocky_sand_clutter.lscene", "", 3},
};

std::string Key(const Input& in) {
  return in.scene + " " + (in.capture.empty() ? "-" : in.capture) + " " + std::to_string(in.seed);
}

// FNV-1a, 64 bits: a digest to compare, not a checksum to trust against tampering.
std::string Digest(const std::string& bytes) {
  uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

std::string PlanDigest(const Input& in) {
  const std::string root = testing::SourceDir() + "/";
  std::optional<std::filesystem::path> capture;
  if (!in.capture.empty()) capture = root + in.capture;
  try {
    const Plan plan =
        MakePlan(root + in.scene, capture, in.seed, {}, gen::MakeFrameEstimatorFactory());
    return Digest(PlanToJson(plan).dump(1));
  } catch (const Error& e) {  // a refused input keeps its message (paths relative to the root)
    std::string message = e.what();
    for (size_t at; (at = message.find(root)) != std::string::npos;) message.erase(at, root.size());
    return "error:" + Digest(message);
  }
}

TEST(PlanGoldens, EveryExamplePlansToItsRecordedBytes) {
  const std::string path = testing::SourceDir() + "/tests/generator/plan_goldens.txt";
  std::map<std::string, std::string> digests;
  for (const Input& in : kInputs) digests[Key(in)] = PlanDigest(in);
  if (std::getenv("LSDS_UPDATE_GOLDEN") != nullptr) {
    std::ofstream out(path);
    out << "# scene capture seed -> FNV-1a of the plan JSON "
           "(tests/generator/plan_goldens_test.cc)\n";
    for (const auto& [key, digest] : digests) out << key << " " << digest << "\n";
    GTEST_SKIP() << "rewrote " << path;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in) << path << " missing: run with LSDS_UPDATE_GOLDEN=1";
  std::map<std::string, std::string> golden;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const size_t space = line.rfind(' ');
    golden[line.substr(0, space)] = line.substr(space + 1);
  }
  EXPECT_EQ(golden.size(), digests.size()) << "inputs and " << path << " list different inputs";
  for (const auto& [key, digest] : digests)
    EXPECT_EQ(golden[key], digest) << key << " plans to other bytes than recorded";
}

}  // namespace
}  // namespace lsds
