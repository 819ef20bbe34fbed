// lsds validate end to end: exit codes, the three report formats, --checks,
// --fail-on, -o.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/collection/schema.h"
#include "tests/build_paths.h"
#include "tests/validate/corruptions.h"
#include "validators/camera_solver_abi.h"
#include "validators/checks.h"

namespace lsds::validate {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code = -1;
  std::string out;
};

CliRun Lsds(const std::string& args) {
  const std::string command = ::lsds::testing::BinaryDir() + "/tools/lsds " + args + " 2>/dev/null";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) run.out.append(buffer, n);
  const int status = pclose(pipe);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

class ValidateCli : public ::testing::Test {
 protected:
  static fs::path Root() {
    return fs::temp_directory_path() / ("lsds_validate_cli_" + std::to_string(getpid()));
  }
  static void SetUpTestSuite() {
    fs::remove_all(Root());
    corpus::WriteGoodCollection(Root() / "good");
    for (const char* name : {"nan-depth", "stray-file", "fov-plus-10"}) {
      corpus::CopyCollection(Root() / "good", Root() / name);
      corpus::FindCorruption(name).apply(Root() / name);
    }
  }
  static void TearDownTestSuite() { fs::remove_all(Root()); }
  static std::string Path(const std::string& name) { return (Root() / name).string(); }
};

TEST_F(ValidateCli, GoodCollectionExitsZero) {
  const CliRun run = Lsds("validate " + Path("good"));
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("PASS: 0 error(s), 0 warning(s) in 4 frame(s)"), std::string::npos)
      << run.out;
}

TEST_F(ValidateCli, FindingsExitOneWithLocation) {
  const CliRun run = Lsds("validate " + Path("nan-depth"));
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.out.find("error layer.depth-finite: 1 finding(s)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("depth/000002.exr frame 2 pixel (10, 7)"), std::string::npos) << run.out;
  // The NaN also disagrees with the bundle's centre sample: a second, genuine
  // finding.
  EXPECT_NE(run.out.find("FAIL: 2 error(s)"), std::string::npos) << run.out;
}

// Ceres is a plug-in (validators/camera_solver_abi.h), opened only when a declared camera must be
// solved: with a broken plug-in a good collection still passes (it is never opened), and a
// collection whose camera needs solving stops with exit code 2 and the plug-in's path.
TEST_F(ValidateCli, TheCameraSolverPlugInIsOpenedOnlyWhenACameraNeedsSolving) {
  const fs::path plugins = Root() / "broken-plugins";
  fs::create_directories(plugins);
  std::ofstream((plugins / kCameraSolverPlugin).string()) << "not a shared library\n";
  // NOLINTNEXTLINE(concurrency-mt-unsafe): the tests of this binary run on one thread
  setenv("LSDS_PLUGIN_DIR", plugins.c_str(), 1);
  const CliRun good = Lsds("validate " + Path("good"));
  const std::string command =
      ::lsds::testing::BinaryDir() + "/tools/lsds validate " + Path("fov-plus-10") + " 2>&1";
  std::string log;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) log.append(buffer, n);
  const int status = pclose(pipe);
  unsetenv("LSDS_PLUGIN_DIR");  // NOLINT(concurrency-mt-unsafe)
  EXPECT_EQ(good.code, 0) << good.out;
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << log;
  EXPECT_NE(log.find("cannot load the plug-in " + (plugins / kCameraSolverPlugin).string()),
            std::string::npos)
      << log;
  // With the real plug-in the same collection's camera is solved and the mistake named.
  const CliRun solved = Lsds("validate " + Path("fov-plus-10"));
  EXPECT_EQ(solved.code, 1) << solved.out;
  EXPECT_NE(solved.out.find("camera.fov"), std::string::npos) << solved.out;
}

TEST_F(ValidateCli, JsonReportMatchesItsSchema) {
  const CliRun run = Lsds("validate --format json " + Path("nan-depth"));
  EXPECT_EQ(run.code, 1);
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_TRUE(JsonSchema::Get("validate-report.schema.json").Validate(report).empty()) << run.out;
  EXPECT_EQ(report["verdict"], "fail");
  bool found = false;
  for (const auto& check : report["checks"]) {
    if (check["id"] != "layer.depth-finite") continue;
    EXPECT_EQ(check["count"], 1);
    const auto& location = check["findings"][0]["location"];
    EXPECT_EQ(location["file"], "depth/000002.exr");
    EXPECT_EQ(location["frame"], 2);
    EXPECT_EQ(location["pixel"], nlohmann::json({10, 7}));
    found = true;
  }
  EXPECT_TRUE(found);
}

TEST_F(ValidateCli, JUnitHasOneTestCasePerCheck) {
  const CliRun run = Lsds("validate --format junit --checks layer " + Path("nan-depth"));
  EXPECT_EQ(run.code, 1);
  size_t testcases = 0, failures = 0;
  for (size_t at = run.out.find("<testcase "); at != std::string::npos;
       at = run.out.find("<testcase ", at + 1)) {
    ++testcases;
  }
  for (size_t at = run.out.find("<failure "); at != std::string::npos;
       at = run.out.find("<failure ", at + 1)) {
    ++failures;
  }
  size_t layer_checks = 0;
  for (const validate::CheckInfo& check : validate::AllChecks())
    layer_checks += check.id.rfind("layer.", 0) == 0;
  EXPECT_EQ(testcases, layer_checks) << run.out;
  EXPECT_EQ(failures, 1u) << run.out;
  EXPECT_NE(run.out.find("name=\"layer.depth-finite\""), std::string::npos);
}

TEST_F(ValidateCli, AnUnreadableInputStillWritesAJUnitReport) {
  const std::string report = Path("unreadable.xml");
  const CliRun run =
      Lsds("validate --format junit -o " + report + " " + Path("no-such-collection"));
  EXPECT_EQ(run.code, 2);
  std::ifstream in(report);
  ASSERT_TRUE(in.good()) << "no JUnit report for an unreadable input";
  const std::string xml((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(xml.find("failures=\"1\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("name=\"collection readable\""), std::string::npos);
  EXPECT_NE(xml.find("no-such-collection"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<testcase classname=\"lsds.validate.input\""), std::string::npos);
}

TEST_F(ValidateCli, FailOnWarning) {
  EXPECT_EQ(Lsds("validate " + Path("stray-file")).code, 0);  // a warning only
  EXPECT_EQ(Lsds("validate --fail-on warning " + Path("stray-file")).code, 1);
}

TEST_F(ValidateCli, UnreadableInputOrBadUsageExitsTwo) {
  EXPECT_EQ(Lsds("validate /nonexistent/collection").code, 2);
  EXPECT_EQ(Lsds("validate --checks layer.nope " + Path("good")).code, 2);
  EXPECT_EQ(Lsds("validate --format yaml " + Path("good")).code, 2);
}

TEST_F(ValidateCli, ReportFileIsNotOverwrittenWithoutForce) {
  const std::string report = Path("report.json");
  EXPECT_EQ(Lsds("validate --format json -o " + report + " " + Path("good")).code, 0);
  EXPECT_TRUE(fs::exists(report));
  EXPECT_EQ(Lsds("validate --format json -o " + report + " " + Path("good")).code, 2);
  EXPECT_EQ(Lsds("validate --format json --force -o " + report + " " + Path("good")).code, 0);
}

// What a CI job array does: each task validates one shard, a last job joins
// them; the joined JUnit equals the single run's (times apart) and the joined
// verdict sets the exit code.
TEST_F(ValidateCli, ShardsJoinedByMergeReportsEqualTheSingleRun) {
  for (const std::string name : {"good", "nan-depth"}) {
    std::string parts;
    for (int i = 0; i < 3; ++i) {
      const std::string part = Path(name + "-part" + std::to_string(i) + ".json");
      const CliRun shard =
          Lsds("validate --shard " + std::to_string(i) + "/3 -o " + part + " " + Path(name));
      EXPECT_EQ(shard.code, 0) << "a shard exits 0 once its report is written";
      parts += " " + part;
    }
    const CliRun single = Lsds("validate --format junit " + Path(name));
    const CliRun merged = Lsds("merge-reports --format junit" + parts);
    EXPECT_EQ(merged.code, single.code) << name;
    EXPECT_EQ(merged.code, name == "good" ? 0 : 1);
    const std::regex time(R"( time="[^"]*")");
    EXPECT_EQ(std::regex_replace(merged.out, time, ""), std::regex_replace(single.out, time, ""))
        << name;
    EXPECT_EQ(Lsds("merge-reports" + parts).out, Lsds("validate " + Path(name)).out)
        << "text reports differ for " << name;
  }
}

TEST_F(ValidateCli, ShardUsageErrorsExitTwo) {
  EXPECT_EQ(Lsds("validate --shard 3/3 -o " + Path("p.json") + " " + Path("good")).code, 2);
  EXPECT_EQ(Lsds("validate --shard 1/x -o " + Path("p.json") + " " + Path("good")).code, 2);
  EXPECT_EQ(Lsds("validate --shard 0/2 " + Path("good")).code, 2);  // no -o
  EXPECT_EQ(
      Lsds("validate --shard 0/2 --format junit -o " + Path("p.json") + " " + Path("good")).code,
      2);
  EXPECT_EQ(Lsds("merge-reports " + Path("no-such-part.json")).code, 2);
  // The report may not replace a partial report it is made from.
  const std::string part = Path("only-part.json");
  ASSERT_EQ(Lsds("validate --shard 0/1 -o " + part + " " + Path("good")).code, 0);
  EXPECT_EQ(Lsds("merge-reports --force -o " + part + " " + part).code, 2);
  EXPECT_EQ(Lsds("merge-reports " + part).code, 0);
}

}  // namespace
}  // namespace lsds::validate
