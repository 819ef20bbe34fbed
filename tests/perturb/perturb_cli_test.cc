// `lsds perturb-metadata` end to end: exit codes, messages, nothing written on
// bad input.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <set>

#include <gtest/gtest.h>

#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_stream.h"
#include "tests/build_paths.h"
#include "tests/perturb/perturb_test_util.h"

namespace lsds {
namespace {

using testing_perturb::ReadText;
using testing_perturb::TempDir;
using testing_perturb::WriteNadirCollection;
namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// `env`: VAR=VALUE assignments for the command's environment.
CliRun Lsds(const std::string& args, const std::string& env = "") {
  const std::string command =
      env + " " + ::lsds::testing::BinaryDir() + "/tools/lsds " + args + " 2>&1";
  CliRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer;
  size_t read;
  while ((read = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    run.output.append(buffer.data(), read);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::set<std::string> Listing(const fs::path& root) {
  std::set<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    names.insert(entry.path().string());
  return names;
}

class PerturbCli : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = WriteNadirCollection(dir_.path() / "c", 10);
    before_ = Listing(dir_.path());
    collection_before_ = ReadText(root_ / "collection.json");
  }
  // Exit 2, the message contains `words`, and no file appeared or changed.
  void ExpectRefused(const std::string& args, const std::string& words) {
    const CliRun run = Lsds("perturb-metadata " + root_.string() + " " + args);
    EXPECT_EQ(run.exit_code, 2) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(words), std::string::npos) << args << "\n" << run.output;
    EXPECT_EQ(Listing(dir_.path()), before_) << args;
    EXPECT_TRUE(ReadText(root_ / "collection.json") == collection_before_) << args;
  }
  TempDir dir_;
  fs::path root_;
  std::set<std::string> before_;
  std::string collection_before_;
};

TEST_F(PerturbCli, WritesRegistersAndReports) {
  const CliRun run = Lsds("perturb-metadata " + root_.string() +
                          " --sigma 1.5,0.2 --sigma-alt 3 --sigma-rot "
                          "0.1,0.1,0.5 --seed 7 --report");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("registered in collection.json"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("p95"), std::string::npos) << run.output;
  EXPECT_TRUE(fs::exists(root_ / "metadata.perturbed-7.json"));
  EXPECT_TRUE(fs::exists(root_ / "metadata.perturbed-7.report.json"));
  const MetadataReader reader(root_ / "metadata.perturbed-7.json");
  const nlohmann::json& sigma = reader.header().noise->parameters["sigma"];
  EXPECT_EQ(sigma["east_m"].get<double>(), 1.5);
  EXPECT_EQ(sigma["up_m"].get<double>(), 3.0);
  EXPECT_EQ(sigma["roll_deg"].get<double>(), 0.1);
  EXPECT_EQ(sigma["yaw_deg"].get<double>(), 0.5);
  EXPECT_EQ(CollectionReader(root_).header().metadata.size(), 2u);

  // Biases and gauss-markov through the command line.
  // (--bias before COLLECTION: each --bias takes exactly one value.)
  const CliRun gm =
      Lsds("perturb-metadata --bias pos=1,2 --bias yaw=0.5 " + root_.string() +
           " --sigma 0 --model gauss-markov --tau 2 --seed 1 -o " + (root_ / "gm.json").string());
  ASSERT_EQ(gm.exit_code, 0) << gm.output;
  StreamJsonArrayMember(root_ / "gm.json", "frames", nullptr, [](nlohmann::json&& frame, size_t) {
    EXPECT_EQ(frame["error"]["position_enu_m"], nlohmann::json::array({1.0, 2.0, 0.0}));
    EXPECT_EQ(frame["error"]["rotation_deg"].get<double>(), 0.5);
  });
}

TEST_F(PerturbCli, SameSeedTwiceIsByteIdentical) {
  ASSERT_EQ(Lsds("perturb-metadata " + root_.string() + " --sigma 2,1 --seed 5 -o " +
                 (root_ / "a.json").string())
                .exit_code,
            0);
  ASSERT_EQ(Lsds("perturb-metadata " + root_.string() + " --sigma 2,1 --seed 5 -o " +
                 (root_ / "b.json").string())
                .exit_code,
            0);
  std::string a = ReadText(root_ / "a.json"), b = ReadText(root_ / "b.json");
  EXPECT_EQ(a, b);
}

TEST_F(PerturbCli, NegativeSigmaIsRefused) {
  ExpectRefused("--sigma-pos=-1 --seed 1", "--sigma-pos");
  ExpectRefused("--sigma -1,0.1 --seed 1", "--sigma");
  ExpectRefused("--sigma-rot 0.1,-0.1,0.1 --seed 1", "--sigma-rot");
}

TEST_F(PerturbCli, UnknownModelIsRefusedWithASuggestion) {
  ExpectRefused("--sigma 1 --seed 1 --model gausian", "did you mean 'gaussian'");
}

TEST_F(PerturbCli, OtherBadUsageIsRefused) {
  ExpectRefused("--seed 1", "no noise given");
  ExpectRefused("--sigma 1 --seed 1 --model gauss-markov", "--tau");
  ExpectRefused("--sigma 1 --seed 1 --tau 3", "--tau");
  ExpectRefused("--sigma 1,2,3 --seed 1", "--sigma");
  ExpectRefused("--sigma abc --seed 1", "not a number");
  ExpectRefused("--sigma 1 --seed 1 --bias heading=3", "unknown field");
  ExpectRefused("--sigma 1", "--seed");
}

TEST_F(PerturbCli, CollectionWithoutMetadataIsRefused) {
  // Unregister every metadata variant (header rewritten through the real
  // writer).
  {
    const CollectionReader reader(root_);
    CollectionHeader header = reader.header();
    header.metadata.clear();
    CollectionWriter writer(root_, header);
    reader.ForEachFrame([&](const Frame& frame) { writer.Append(frame); });
    writer.Commit();
  }
  collection_before_ = ReadText(root_ / "collection.json");
  ExpectRefused("--sigma 1 --seed 1", "no truth metadata");
}

TEST_F(PerturbCli, MissingMetadataFileIsRefused) {
  fs::remove(root_ / "metadata.json");
  before_ = Listing(dir_.path());
  ExpectRefused("--sigma 1 --seed 1", "does not exist");
}

TEST_F(PerturbCli, ExistingOutputIsRefusedWithoutForce) {
  ASSERT_EQ(Lsds("perturb-metadata " + root_.string() + " --sigma 1 --seed 3").exit_code, 0);
  before_ = Listing(dir_.path());
  collection_before_ = ReadText(root_ / "collection.json");
  const std::string first = ReadText(root_ / "metadata.perturbed-3.json");
  ExpectRefused("--sigma 5 --seed 3", "--force");
  EXPECT_TRUE(ReadText(root_ / "metadata.perturbed-3.json") == first);
  const CliRun forced = Lsds("perturb-metadata " + root_.string() + " --sigma 5 --seed 3 --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_TRUE(ReadText(root_ / "metadata.perturbed-3.json") != first);
}

TEST_F(PerturbCli, NotACollectionIsRefused) {
  const CliRun run =
      Lsds("perturb-metadata " + (dir_.path() / "nothing").string() + " --sigma 1 --seed 1");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("does not exist"), std::string::npos) << run.output;
}

// Eight writers registering variants at once: the folder lock makes them take
// turns, so every registration survives (without it, each rewrites the header
// it read and all but one are lost).
TEST_F(PerturbCli, ConcurrentWritersAllRegister) {
  std::string script;
  for (int seed = 1; seed <= 8; ++seed) {
    script += ::lsds::testing::BinaryDir() + "/tools/lsds perturb-metadata " + root_.string() +
              " --sigma 1 --seed " + std::to_string(seed) + " >/dev/null 2>&1 & ";
  }
  script += "wait";
  // NOLINTNEXTLINE(concurrency-mt-unsafe): the test starts no threads
  ASSERT_EQ(std::system(("sh -c '" + script + "'").c_str()), 0);
  const CollectionReader reader(root_);
  std::set<std::string> files;
  for (const MetadataVariant& variant : reader.header().metadata) files.insert(variant.file);
  EXPECT_EQ(files.size(), 9u);  // the truth and eight variants
  for (int seed = 1; seed <= 8; ++seed) {
    EXPECT_EQ(files.count("metadata.perturbed-" + std::to_string(seed) + ".json"), 1u) << seed;
  }
}

TEST_F(PerturbCli, RefusesOutputsOntoInputsEvenWithForce) {
  ExpectRefused("--sigma 1 --seed 3 -o " + (root_ / "collection.json").string() + " --force",
                "is the collection file");
  ExpectRefused("--sigma 1 --seed 3 -o " + (root_ / "metadata.json").string() + " --force",
                "is the truth metadata");
  ExpectRefused("--sigma 1 --seed 3 -o " + root_.string() + " --force",
                "an input of lsds perturb-metadata");
}

// A report that cannot be written is found before anything is renamed into
// place: no variant is left behind, unregistered, without its report.
TEST_F(PerturbCli, AReportThatCannotBeWrittenLeavesNoVariant) {
  fs::create_directories(dir_.path() / "taken" / "inside");
  before_ = Listing(dir_.path());
  ExpectRefused("--sigma 1 --seed 3 --force --report=" + (dir_.path() / "taken").string(),
                "the report is a folder");
}

// A full disk at any moment (simulated: checked writes fail with ENOSPC after
// N bytes) leaves all or nothing: never a variant without its report, nor a
// registered variant without its file.
TEST_F(PerturbCli, AFullDiskAtAnyMomentLeavesAllOrNothing) {
  const std::string args =
      "perturb-metadata " + root_.string() + " --sigma 1,0.5 --seed 4 --report";
  int failures = 0;
  bool written = false;
  for (int budget = 0; budget < 1000000 && !written; budget += 1000) {
    const CliRun run = Lsds(args, "LSDS_FAULT_WRITE_BYTES=" + std::to_string(budget));
    if (run.exit_code == 0) {
      written = true;
      break;
    }
    ++failures;
    EXPECT_EQ(run.exit_code, 2) << budget << "\n" << run.output;
    EXPECT_NE(run.output.find("error: " + root_.string() + "/"), std::string::npos)
        << budget << "\n"
        << run.output;
    EXPECT_NE(run.output.find("No space left on device"), std::string::npos) << budget << "\n"
                                                                             << run.output;
    EXPECT_EQ(Listing(dir_.path()), before_) << budget;
    EXPECT_TRUE(ReadText(root_ / "collection.json") == collection_before_) << budget;
  }
  ASSERT_TRUE(written);
  EXPECT_GT(failures, 3);  // the budgets reached every file, the report last
  EXPECT_TRUE(fs::exists(root_ / "metadata.perturbed-4.json"));
  EXPECT_TRUE(fs::exists(root_ / "metadata.perturbed-4.report.json"));
  EXPECT_EQ(CollectionReader(root_).header().metadata.size(), 2u);
}

}  // namespace
}  // namespace lsds
