// End-to-end: the lsds binary on synthetic collections and on bad input.
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
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

// lsds info shows what the files store, not only what readers get: the default
// generator writes plain FLOAT worldposition and motion, --compact UINT
// residuals that every lsds reader decodes to the same FLOAT X, Y, Z.
TEST(Cli, InfoShowsTheStoredChannelsAndLayout) {
  testing::TempDir dir;
  const std::string demo = " generate --demo --demo-frames 2 --demo-size 16x12 --spp 1 --quiet -o ";
  for (const std::string& extra : {"", " --compact"}) {
    const fs::path out = dir / (extra.empty() ? "default" : "compact");
    const auto g = RunCommandLine(testing::LsdsBinary() + demo + out.string() + extra);
    ASSERT_EQ(g.exit_code, 0) << g.output;
  }
  std::map<std::string, nlohmann::json> layers[2];
  std::string text[2];
  for (int k = 0; k < 2; ++k) {
    const fs::path out = dir / (k == 0 ? "default" : "compact");
    const auto json = RunCommandLine(testing::LsdsBinary() + " info --json " + out.string());
    ASSERT_EQ(json.exit_code, 0) << json.output;
    const nlohmann::json info = nlohmann::json::parse(json.output);
    for (const auto& layer : info["layers"]) layers[k][layer["name"]] = layer;
    text[k] = RunCommandLine(testing::LsdsBinary() + " info " + out.string()).output;
  }
  const nlohmann::json xyz = {"X:float", "Y:float", "Z:float"}, xy = {"X:float", "Y:float"};
  EXPECT_EQ(layers[0]["worldposition"]["channels"], xyz);
  EXPECT_EQ(layers[0]["worldposition"]["read_as"], xyz);
  EXPECT_EQ(layers[0]["worldposition"]["layout"], "float");
  EXPECT_EQ(layers[0]["motion"]["channels"], xy);
  EXPECT_EQ(layers[0]["motion"]["layout"], "float");
  EXPECT_EQ(layers[0]["bundle"]["layout"], "residual");
  EXPECT_FALSE(layers[0]["depth"].contains("layout"));
  EXPECT_EQ(layers[1]["worldposition"]["channels"],
            nlohmann::json({"dX:uint", "dY:uint", "dZ:uint"}));
  EXPECT_EQ(layers[1]["worldposition"]["read_as"], xyz);
  EXPECT_EQ(layers[1]["worldposition"]["layout"], "residual");
  EXPECT_EQ(layers[1]["motion"]["channels"], nlohmann::json({"dX:uint", "dY:uint"}));
  EXPECT_EQ(layers[1]["motion"]["layout"], "residual");
  EXPECT_NE(text[0].find("X:float,Y:float,Z:float"), std::string::npos) << text[0];
  EXPECT_NE(text[0].find("layout float\n"), std::string::npos) << text[0];
  EXPECT_NE(text[1].find("dX:uint,dY:uint,dZ:uint"), std::string::npos) << text[1];
  EXPECT_NE(text[1].find("layout residual, read as X:float,Y:float,Z:float"), std::string::npos)
      << text[1];
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
