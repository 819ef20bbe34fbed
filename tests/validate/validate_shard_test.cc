// lsds validate --shard I/N + lsds merge-reports: for the good collection and
// every corruption of the defect corpus, the partial reports of N shards,
// written to files and joined, give the single run's report in text, JSON and
// JUnit (all but the measured times), also when the examples kept per check
// are fewer than the findings (the first ones by frame must survive the join).
#include <unistd.h>

#include <fstream>
#include <regex>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/util/error.h"
#include "tests/validate/corruptions.h"
#include "validators/partial_report.h"
#include "validators/report_writers.h"
#include "validators/validate.h"

namespace lsds::validate {
namespace {

namespace fs = std::filesystem;

fs::path TestRoot() {
  static const fs::path root =
      fs::temp_directory_path() / ("lsds_validate_shard_test_" + std::to_string(getpid()));
  return root;
}

// The measured times are the only part of a report two runs may differ in.
std::string WithoutTimes(const std::string& format, std::string text) {
  if (format == "json") {
    nlohmann::json j = nlohmann::json::parse(text);
    j.erase("seconds");
    for (nlohmann::json& check : j["checks"]) check.erase("seconds");
    return j.dump(2);
  }
  if (format == "junit") return std::regex_replace(text, std::regex(R"( time="[^"]*")"), "");
  return text;
}

std::vector<fs::path> WriteShards(const fs::path& collection,
                                  const ValidateOptions& base,
                                  int count,
                                  const fs::path& folder) {
  fs::create_directories(folder);
  std::vector<fs::path> files;
  // Written in reverse order: the join must not depend on the order given.
  for (int i = count - 1; i >= 0; --i) {
    ValidateOptions options = base;
    options.shard_index = i;
    options.shard_count = count;
    const PartialReport partial = ValidateShard(collection, options);
    files.push_back(folder / ("part" + std::to_string(i) + ".json"));
    std::ofstream(files.back()) << PartialReportToJson(partial).dump(1);
  }
  return files;
}

void ExpectMergeEqualsSingleRun(const fs::path& collection,
                                const ValidateOptions& options,
                                int count) {
  const Report single = ValidateCollection(collection, options);
  const Report merged = MergePartialReports(WriteShards(
      collection, options, count, TestRoot() / ("parts_" + collection.filename().string())));
  EXPECT_EQ(merged.frames, single.frames);
  EXPECT_EQ(merged.files_decoded, single.files_decoded);
  for (const char* format : {"text", "json", "junit"}) {
    for (Severity fail_on : {Severity::kError, Severity::kInfo}) {
      EXPECT_EQ(WithoutTimes(format, RenderReport(merged, format, fail_on)),
                WithoutTimes(format, RenderReport(single, format, fail_on)))
          << collection << " in " << format << " with " << count << " shards";
    }
  }
}

class ShardTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(TestRoot());
    corpus::WriteGoodCollection(TestRoot() / "good");
  }
  static void TearDownTestSuite() { fs::remove_all(TestRoot()); }
};

TEST_F(ShardTest, GoodCollectionInOneToFiveShards) {
  for (int count : {1, 2, 3, 5}) {  // 5 > 4 frames: a shard with no frame
    ExpectMergeEqualsSingleRun(TestRoot() / "good", {}, count);
  }
}

TEST_F(ShardTest, EveryCorruptionOfTheCorpus) {
  ValidateOptions options;
  options.max_examples = 1;  // fewer kept than found: the join must pick
  for (const corpus::Corruption& c : corpus::Corruptions()) {
    const fs::path root = TestRoot() / c.name;
    corpus::CopyCollection(TestRoot() / "good", root);
    c.apply(root);
    ExpectMergeEqualsSingleRun(root, options, 3);
  }
}

TEST_F(ShardTest, ChecksTimesAreMeasured) {
  const Report report = ValidateCollection(TestRoot() / "good");
  double sum = 0;
  for (const auto& [id, seconds] : report.check_seconds()) {
    EXPECT_GE(seconds, 0) << id;
    sum += seconds;
  }
  // Decoding four frames' EXRs takes time, and every check that ran on them
  // is charged: layer.readable holds the decoding.
  EXPECT_GT(report.check_seconds().at("layer.readable"), 0);
  EXPECT_GT(sum, 0);
  const std::string junit = RenderReport(report, "junit", Severity::kError);
  EXPECT_EQ(std::regex_search(junit, std::regex(R"(<testcase [^>]*time="[0-9.]+")")), true);
}

TEST_F(ShardTest, IncompleteOrMixedShardsAreRefusedWithTheFile) {
  const fs::path folder = TestRoot() / "refused";
  std::vector<fs::path> files = WriteShards(TestRoot() / "good", {}, 3, folder);
  auto message = [](const std::vector<fs::path>& given) {
    try {
      MergePartialReports(given);
    } catch (const Error& e) {
      return e.location().ToString() + ": " + e.message();
    }
    return std::string("no error");
  };
  // One missing (files[0] is shard 2: written in reverse).
  EXPECT_NE(message({files[1], files[2]}).find("shard(s) 2/3 missing"), std::string::npos)
      << message({files[1], files[2]});
  // One twice.
  const std::string twice = message({files[0], files[1], files[2], files[1]});
  EXPECT_NE(twice.find("given twice"), std::string::npos) << twice;
  // A shard of another collection.
  const fs::path other = TestRoot() / "other";
  corpus::CopyCollection(TestRoot() / "good", other);
  corpus::FindCorruption("nan-depth").apply(other);
  {
    // nan-depth changes a layer file, not collection.json: change the header.
    nlohmann::json collection;
    std::ifstream(other / "collection.json") >> collection;
    collection["name"] = "another run";
    std::ofstream(other / "collection.json") << collection.dump(1);
  }
  ValidateOptions options;
  options.shard_index = 0;
  options.shard_count = 3;
  std::ofstream(folder / "other0.json")
      << PartialReportToJson(ValidateShard(other, options)).dump();
  const std::string mixed = message({folder / "other0.json", files[1], files[0]});
  EXPECT_NE(mixed.find("not shards of one run"), std::string::npos) << mixed;
  // Not a partial report at all: located at /format.
  std::ofstream(folder / "report.json") << R"({"format": "lsds-validate-report"})";
  const std::string wrong = message({folder / "report.json"});
  EXPECT_NE(wrong.find("report.json#/format"), std::string::npos) << wrong;
  // A schema violation names its JSON pointer.
  nlohmann::json bad;
  std::ifstream(files[0]) >> bad;
  bad["frames"] = -3;
  std::ofstream(folder / "bad.json") << bad.dump();
  const std::string located = message({folder / "bad.json", files[1], files[2]});
  EXPECT_NE(located.find("bad.json#/frames"), std::string::npos) << located;
}

TEST(ShardOptions, ShardIndexMustBeBelowCount) {
  ValidateOptions options;
  options.shard_index = 3;
  options.shard_count = 3;
  EXPECT_THROW(ValidateShard("/nonexistent", options), Error);
}

}  // namespace
}  // namespace lsds::validate
