// End-to-end: the lsds binary on synthetic collections and on bad input.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

using testing::RunCommandLine;

TEST(Cli, VersionHelpAndUnknownCommand) {
  EXPECT_EQ(RunCommandLine(testing::LsdsBinary() + " --version").exit_code, 0);
  const auto help = RunCommandLine(testing::LsdsBinary() + " help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("info"), std::string::npos);
  const auto unknown = RunCommandLine(testing::LsdsBinary() + " inf");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("did you mean 'info'"), std::string::npos);
  EXPECT_EQ(RunCommandLine(testing::LsdsBinary() + " info").exit_code,
            2);  // missing argument
}

TEST(Cli, InfoSummarizesACollection) {
  testing::TempDir dir;
  synth::Spec spec = synth::DefaultSpec();
  spec.width = 32, spec.height = 24;
  synth::WriteCollection(dir / "c", spec);
  const auto result =
      RunCommandLine(testing::LsdsBinary() + " info --json " + (dir / "c").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json info = nlohmann::json::parse(result.output);
  EXPECT_EQ(info["frames"], 4);
  EXPECT_EQ(info["cameras"]["resolutions"]["32x24"], 4);
  EXPECT_EQ(info["layers"].size(), 9u);
  int boxes = 0;
  for (const auto& c : info["classes"]) {
    if (c["name"] == "box") boxes = c["instances"];
  }
  EXPECT_EQ(boxes, 2);
  EXPECT_GT(info["bytes"].get<int64_t>(), 0);
  const auto text = RunCommandLine(testing::LsdsBinary() + " info " + (dir / "c").string());
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.output.find("bundle"), std::string::npos);
}

TEST(Cli, InfoFailsCleanlyOnANonCollection) {
  testing::TempDir dir;
  const auto result = RunCommandLine(testing::LsdsBinary() + " info " + dir.path().string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find(dir.path().string()), std::string::npos);
  EXPECT_NE(result.output.find("collection.json"), std::string::npos);
}

}  // namespace
}  // namespace lsds
