// End-to-end: `lsds plan` on the examples.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "../test_util.h"
#include "tests/build_paths.h"

namespace lsds {
namespace {

using testing::LsdsBinary;
using testing::RunCommandLine;
using testing::TempDir;

const std::string kExamples = ::lsds::testing::ExamplesDir();

TEST(LangCli, PlanWritesTheSameFileForTheSameSeed) {
  TempDir dir;
  const std::string base = LsdsBinary() + " plan " + kExamples + "/paper_example1.lscene " +
                           kExamples + "/paper_example1.lcap --seed 5 -o ";
  ASSERT_EQ(RunCommandLine(base + (dir / "a.json").string()).exit_code, 0);
  ASSERT_EQ(RunCommandLine(base + (dir / "b.json").string()).exit_code, 0);
  std::ifstream a(dir / "a.json"), b(dir / "b.json");
  const std::string ta((std::istreambuf_iterator<char>(a)), {}),
      tb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(ta, tb);
  EXPECT_EQ(nlohmann::json::parse(ta)["frame_count"], 60);
  // Refuses to overwrite without --force.
  const auto again = RunCommandLine(base + (dir / "a.json").string());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_EQ(RunCommandLine(base + (dir / "a.json").string() + " --force").exit_code, 0);
  // A frame subset.
  const auto part = RunCommandLine(base + (dir / "c.json").string() + " --frames 10:12");
  ASSERT_EQ(part.exit_code, 0) << part.output;
  std::ifstream c(dir / "c.json");
  const nlohmann::json pc = nlohmann::json::parse(c);
  EXPECT_EQ(pc["frames"][0], nlohmann::json::parse(ta)["frames"][10]);
}

TEST(LangCli, EmitJsonPrintsTheJsonFormThatPlansTheSame) {
  TempDir dir;
  const auto emitted =
      RunCommandLine(LsdsBinary() + " plan " + kExamples + "/uav_survey.lscene --emit-json -o " +
                     (dir / "s.json").string());
  ASSERT_EQ(emitted.exit_code, 0) << emitted.output;
  const auto text =
      RunCommandLine(LsdsBinary() + " plan " + kExamples + "/uav_survey.lscene --seed 3");
  const auto json =
      RunCommandLine(LsdsBinary() + " plan " + (dir / "s.json").string() + " --seed 3");
  ASSERT_EQ(text.exit_code, 0);
  ASSERT_EQ(json.exit_code, 0) << json.output;
  nlohmann::json a = nlohmann::json::parse(text.output), b = nlohmann::json::parse(json.output);
  a.erase("scene_source");
  b.erase("scene_source");
  EXPECT_EQ(a, b);
}

TEST(LangCli, BadInputExitsTwoWithTheLocation) {
  TempDir dir;
  std::ofstream(dir / "bad.lscene") << "LSCENE = ONE(O1)\nO1 = object{clas:cube}\n";
  const auto r = RunCommandLine(LsdsBinary() + " plan " + (dir / "bad.lscene").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.lscene:2:13: unknown key 'clas' in object O1 "
                          "(did you mean 'class'?)"),
            std::string::npos)
      << r.output;
  const auto missing = RunCommandLine(LsdsBinary() + " plan " + (dir / "nope.lscene").string());
  EXPECT_EQ(missing.exit_code, 2);
}

}  // namespace
}  // namespace lsds
