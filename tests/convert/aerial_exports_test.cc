// The aerial and tracking exports end to end, as a user meets them: a capture
// with a truck driving a road under a crate (partly hidden) seen by a nadir +
// oblique rig is generated, gated by `lsds validate --fail-on warning`,
// converted to every format, whole frames and tiles, and each export read
// back by `lsds check-export` with its consumers' own loading rules: nothing
// a trainer or an evaluator would drop.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>

#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

class AerialExports : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string examples = ExamplesDir();
    std::ifstream in(examples + "/time_of_day_movers.lcap");
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    // Small frames, nothing else changed.
    std::ofstream(*dir_ / "c.lcap")
        << std::regex_replace(text, std::regex(R"(res:\[[0-9]+,[0-9]+\])"), "res:[320,240]");
    generated_ =
        RunLsds("generate " + examples + "/time_of_day_movers.lscene " +
                (*dir_ / "c.lcap").string() + " -o " + Collection() + " --spp 1 --seed 3 -q");
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string Collection() { return (*dir_ / "collection").string(); }
  static std::string Out(const std::string& name) { return (*dir_ / name).string(); }

  static TempDir* dir_;
  static CommandResult generated_;
};
TempDir* AerialExports::dir_ = nullptr;
CommandResult AerialExports::generated_;

TEST_F(AerialExports, TheCapturePassesTheGate) {
  ASSERT_EQ(generated_.exit_code, 0) << generated_.output;
  const CommandResult validated = RunLsds("validate " + Collection() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
}

class EveryFormat : public AerialExports, public ::testing::WithParamInterface<std::string> {};

TEST_P(EveryFormat, NoConsumerDropsAnything) {
  ASSERT_EQ(generated_.exit_code, 0) << generated_.output;
  const std::string format = GetParam();
  for (const std::string tiles : {"", " --tile 200 --overlap 40"}) {
    const std::string out = Out(format + (tiles.empty() ? "" : "_tiles"));
    const CommandResult converted =
        RunLsds("convert " + Collection() + " --to " + format + tiles + " -o " + out + " -q");
    ASSERT_EQ(converted.exit_code, 0) << converted.output;
    // mot writes its benchmark folder under mot/ (TrackEval's GT_FOLDER).
    const std::string folder = format == "mot" ? out + "/mot" : out;
    const CommandResult checked = RunLsds("check-export " + format + " " + folder);
    EXPECT_EQ(checked.exit_code, 0) << format << tiles << "\n" << checked.output;
  }
}

INSTANTIATE_TEST_SUITE_P(Formats,
                         EveryFormat,
                         ::testing::Values("yolo", "yolo-seg", "yolo-obb", "dota", "coco", "mot"),
                         [](const auto& info) {
                           return std::regex_replace(info.param, std::regex("-"), "_");
                         });

}  // namespace
}  // namespace lsds::testing
