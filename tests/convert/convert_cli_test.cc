// `lsds convert` end to end: outputs that two runs race for.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::LsdsBinary;
using testing::RunCommandLine;

// Two converts to the same new output started at once: both find it absent
// when they start, and both build it under a temporary name. Exactly one may
// put its folder there; the other exits 2 naming the output (whether it meets
// the folder at its start or at its rename) and replaces nothing.
TEST(ConvertCli, TwoConvertsToOneNewOutputCannotBothSucceed) {
  const testing::TempDir dir;
  const fs::path collection = dir / "C";
  const testing::CommandResult synth =
      RunCommandLine(LsdsBinary() + " synth " + collection.string() + " --count 6 --size 96x64");
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const fs::path out = dir / "out";
  for (int round = 0; round < 3; ++round) {
    fs::remove_all(out);
    const std::string convert = "CI=true " + LsdsBinary() + " convert " + collection.string() +
                                " --to coco --images png -o " + out.string();
    const testing::CommandResult r = RunCommandLine(
        convert + " >" + (dir / "a.log").string() + " 2>&1 & a=$!; " + convert + " >" +
        (dir / "b.log").string() + " 2>&1 & b=$!; wait $a; echo a=$?; " +
        "wait $b; echo b=$?; cat " + (dir / "a.log").string() + " " + (dir / "b.log").string());
    std::smatch codes;
    ASSERT_TRUE(std::regex_search(r.output, codes, std::regex("a=(\\d+)\\nb=(\\d+)"))) << r.output;
    const int a = std::stoi(codes[1]), b = std::stoi(codes[2]);
    EXPECT_EQ(std::min(a, b), 0) << r.output;
    EXPECT_EQ(std::max(a, b), 2) << r.output;
    EXPECT_NE(r.output.find("error: " + out.string() + ": "), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_directory(out / "annotations")) << r.output;
    // The loser's temporary folder is gone.
    for (const auto& entry : fs::directory_iterator(dir.path()))
      EXPECT_EQ(entry.path().filename().string().find("lsds-tmp"), std::string::npos)
          << entry.path();
  }
}

}  // namespace
}  // namespace lsds
