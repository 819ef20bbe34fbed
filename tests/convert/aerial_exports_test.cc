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

#include <nlohmann/json.hpp>

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

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

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
    const std::string report = out + "_check.json";
    const CommandResult checked =
        RunLsds("check-export " + format + " " + folder + " --format json -o " + report);
    ASSERT_TRUE(checked.exit_code == 0 || checked.exit_code == 1) << checked.output;
    // The one loss a consumer may see is the one the loss report already
    // names: MMRotate leaves images without objects out of training.
    int64_t empty_images = 0;
    const nlohmann::json findings = ReadJson(report).at("findings");
    for (const nlohmann::json& finding : findings) {
      const std::string severity = finding.at("severity").get<std::string>();
      const std::string rule = finding.at("rule").get<std::string>();
      if (severity == "ignored") continue;
      if (format == "dota" && rule == "mmrotate.empty-image") {
        ++empty_images;
        continue;
      }
      ADD_FAILURE() << format << tiles << ": " << finding.dump();
    }
    const nlohmann::json counts = ReadJson(out + "/loss_report.json").at("counts");
    const std::string reason = "dota: images without objects (MMRotate skips them when training)";
    EXPECT_EQ(empty_images,
              counts.contains(reason) ? counts.at(reason).at("total").get<int64_t>() : 0)
        << format << tiles;
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
