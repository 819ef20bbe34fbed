// lsds merge end to end: a small survey rendered once whole and once in three
// shards; the merged shards must equal the whole run byte for byte, and shard
// sets that are not one run must be refused naming the frames.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::LsdsBinary;
using testing::RunCommandLine;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every regular file under `root` by relative path, with its bytes.
std::map<std::string, std::string> Tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file())
      files[fs::relative(entry.path(), root).string()] = Slurp(entry.path());
  return files;
}

class MergeCliTest : public ::testing::Test {
 protected:
  // 12 frames (a 4 x 3 grid) at 64x48, one sample per pixel.
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    std::string capture =
        Slurp(fs::path(::lsds::testing::SourceDir()) / "examples" / "demo_survey.lcap");
    capture = std::regex_replace(capture, std::regex(R"(res:\[512,512\])"), "res:[64,48]");
    capture = std::regex_replace(capture, std::regex(R"(x:\[-40,40,6\])"), "x:[-40,40,4]");
    capture = std::regex_replace(capture, std::regex(R"(y:\[-25,25,4\])"), "y:[-25,25,3]");
    std::ofstream(*dir_ / "small.lcap") << capture;
    ASSERT_EQ(Generate("whole", ""), 0);
    for (int i = 0; i < 3; ++i)
      ASSERT_EQ(Generate("s" + std::to_string(i), "--shard " + std::to_string(i) + "/3"), 0);
  }
  static void TearDownTestSuite() { delete dir_; }

  // --compact: the residual motion of a shard's frame refers to the previous frame's camera,
  // which another shard rendered; the merge keeps it exact.
  static int Generate(const std::string& out,
                      const std::string& extra,
                      int seed = 3,
                      const std::string& layouts = "--compact") {
    const testing::CommandResult r =
        RunCommandLine("CI=true " + LsdsBinary() + " generate " + ::lsds::testing::SourceDir() +
                       "/examples/uav_survey.lscene " + (*dir_ / "small.lcap").string() + " " +
                       layouts + " --spp 1 -q --seed " + std::to_string(seed) + " " + extra +
                       " -o " + (*dir_ / out).string());
    if (r.exit_code != 0) ADD_FAILURE() << r.output;
    return r.exit_code;
  }
  static testing::CommandResult Merge(const std::string& shards, const std::string& out) {
    std::string args;
    std::istringstream names(shards);
    for (std::string name; names >> name;) args += " " + (*dir_ / name).string();
    return RunCommandLine("CI=true " + LsdsBinary() + " merge" + args + " -o " +
                          (*dir_ / out).string());
  }
  static fs::path Path(const std::string& name) { return *dir_ / name; }

  static testing::TempDir* dir_;
};
testing::TempDir* MergeCliTest::dir_ = nullptr;

TEST_F(MergeCliTest, MergedShardsEqualTheSingleRunByteForByte) {
  const auto before = Tree(Path("s1"));
  const testing::CommandResult r = Merge("s2 s0 s1", "merged");  // any order
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto whole = Tree(Path("whole"));
  const auto merged = Tree(Path("merged"));
  ASSERT_EQ(whole.size(), merged.size());
  EXPECT_GT(whole.size(), 12u * 5);  // collection.json, metadata.json, layers
  for (const auto& [name, bytes] : whole) {
    const auto it = merged.find(name);
    ASSERT_NE(it, merged.end()) << name << " missing from the merged run";
    EXPECT_TRUE(it->second == bytes) << name << " differs";
  }
  EXPECT_EQ(Tree(Path("s1")), before);  // the shards are only read
  // A shard is a partial collection and says so; the merged one does not.
  EXPECT_NE(Slurp(Path("s1") / "collection.json").find("\"shard\""), std::string::npos);
  const testing::CommandResult v =
      RunCommandLine("CI=true " + LsdsBinary() + " validate " + Path("merged").string());
  EXPECT_EQ(v.exit_code, 0) << v.output;
}

TEST_F(MergeCliTest, AMissingShardNamesItsFrames) {
  const testing::CommandResult r = Merge("s0 s1", "missing");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("frames 2, 5, 8 and 11 are in no shard given: "
                          "shard 2/3"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("missing")));
}

TEST_F(MergeCliTest, ADoubledShardNamesItsFrames) {
  const testing::CommandResult r = Merge("s0 s1 s2 s1", "doubled");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("frames 1, 4, 7 and 10 are in more than one shard"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("doubled")));
}

TEST_F(MergeCliTest, AShardOfAnotherSeedIsRefusedNamingTheField) {
  ASSERT_EQ(Generate("seed4_s2", "--shard 2/3", 4), 0);
  const testing::CommandResult r = Merge("s0 s1 seed4_s2", "mixed");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("seed4_s2/collection.json#/provenance/seed: not a "
                          "shard of the same run"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("mixed")));
}

TEST_F(MergeCliTest, ShardsOfAnotherShardCountAreRefused) {
  ASSERT_EQ(Generate("half1", "--shard 1/2"), 0);
  const testing::CommandResult r = Merge("s0 half1", "counts");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("#/provenance/shard/count"), std::string::npos) << r.output;
}

TEST_F(MergeCliTest, AWholeRunOrAnUnfinishedShardIsNotMerged) {
  testing::CommandResult r = Merge("s0 s1 whole", "notashard");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a shard"), std::string::npos) << r.output;
  fs::copy(Path("s2"), Path("s2_unfinished"), fs::copy_options::recursive);
  fs::create_directory(Path("s2_unfinished") / ".lsds-generate");
  r = Merge("s0 s1 s2_unfinished", "unfinished");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("the shard is unfinished"), std::string::npos) << r.output;
}

TEST_F(MergeCliTest, OutputsAreNeverInsideInputsNorReplacedWithoutForce) {
  testing::CommandResult r = Merge("s0 s1 s2", "s1/inside");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(Path("s1") / "inside"));
  fs::create_directory(Path("taken"));
  std::ofstream(Path("taken") / "keep.txt") << "user data";
  r = Merge("s0 s1 s2", "taken");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(Path("taken") / "keep.txt"));
}

// A copy of shard `name` in which `mutate` changes one thing; the merge of
// s0, the copy (in place of s1) and s2 must be refused naming the file.
fs::path MutatedShard(const fs::path& shard, const std::string& name) {
  fs::path copy = shard.parent_path() / name;
  fs::remove_all(copy);
  fs::copy(shard, copy, fs::copy_options::recursive | fs::copy_options::copy_symlinks);
  return copy;
}

TEST_F(MergeCliTest, ALayerLinkedOutsideTheShardIsNotCopied) {
  const fs::path shard = MutatedShard(Path("s1"), "s1_link");
  std::ofstream(Path("secret.txt")) << "not a layer\n";
  fs::remove(shard / "depth" / "000004.exr");
  fs::create_symlink(Path("secret.txt"), shard / "depth" / "000004.exr");
  const testing::CommandResult r = Merge("s0 s1_link s2", "linked");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(
      r.output.find("s1_link/depth/000004.exr frame 4: the layer file is a symbolic link (to " +
                    Path("secret.txt").string() + ")"),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("linked")));
  // A linked layer folder is refused the same way.
  fs::remove(shard / "depth" / "000004.exr");
  fs::copy_file(Path("s1") / "depth" / "000004.exr", shard / "depth" / "000004.exr");
  fs::rename(shard / "normal", Path("s1_normal"));
  fs::create_directory_symlink(Path("s1_normal"), shard / "normal");
  const testing::CommandResult folder = Merge("s0 s1_link s2", "linked");
  EXPECT_EQ(folder.exit_code, 2) << folder.output;
  EXPECT_NE(folder.output.find("its folder " + (shard / "normal").string() + " is a symbolic link"),
            std::string::npos)
      << folder.output;
  EXPECT_FALSE(fs::exists(Path("linked")));
}

TEST_F(MergeCliTest, AFifoInAShardIsRefusedWithoutBlocking) {
  const fs::path shard = MutatedShard(Path("s1"), "s1_fifo");
  fs::remove(shard / "rgb" / "000007.exr");
  ASSERT_EQ(::mkfifo((shard / "rgb" / "000007.exr").c_str(), 0644), 0);
  const testing::CommandResult r = Merge("s0 s1_fifo s2", "fifo");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("s1_fifo/rgb/000007.exr frame 7: the layer file is a FIFO"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("fifo")));
}

TEST_F(MergeCliTest, ATruncatedLayerIsRefusedNamingFileAndFrame) {
  const fs::path shard = MutatedShard(Path("s1"), "s1_cut");
  const fs::path layer = shard / "depth" / "000010.exr";
  fs::resize_file(layer, fs::file_size(layer) - 100);
  const testing::CommandResult r = Merge("s0 s1_cut s2", "cut");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("s1_cut/depth/000010.exr frame 10: layer 'depth': truncated"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("cut")));
}

TEST_F(MergeCliTest, ALayerThatIsNotTheDeclaredOneIsRefused) {
  const fs::path shard = MutatedShard(Path("s1"), "s1_swapped");
  fs::copy_file(Path("s1") / "rgb" / "000001.exr",
                shard / "depth" / "000001.exr",
                fs::copy_options::overwrite_existing);
  const testing::CommandResult r = Merge("s0 s1_swapped s2", "swapped");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("s1_swapped/depth/000001.exr frame 1: layer 'depth': the file has "
                          "no channel"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("swapped")));
}

// The demo's scene has no text: its parameters are its source, so shards of
// demos of two sizes are two runs.
TEST_F(MergeCliTest, ShardsOfDemosOfDifferentSizesAreRefused) {
  auto demo = [](const std::string& size, const std::string& shard, const std::string& out) {
    const testing::CommandResult r =
        RunCommandLine("CI=true " + LsdsBinary() + " generate --demo --demo-frames 4 --demo-size " +
                       size + " --spp 1 -q --shard " + shard + " -o " + Path(out).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
  };
  demo("32x24", "0/2", "demo_a0");
  demo("40x24", "1/2", "demo_b1");
  const testing::CommandResult r = Merge("demo_a0 demo_b1", "demos");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("demo_b1/collection.json#/provenance/scene_source: not a shard of the "
                          "same run"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--demo-size 40x24"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--demo-size 32x24"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("demos")));
  // Shards of one demo still merge into its single run.
  demo("32x24", "1/2", "demo_a1");
  const testing::CommandResult same = Merge("demo_a1 demo_a0", "demo_merged");
  EXPECT_EQ(same.exit_code, 0) << same.output;
}

// A full disk (simulated: writes fail with ENOSPC after N bytes) is reported
// naming the merged output, never a shard's file, and leaves no output.
TEST_F(MergeCliTest, AFullDiskNamesTheOutput) {
  for (const int budget : {0, 20000, 200000}) {
    const testing::CommandResult r =
        RunCommandLine("LSDS_FAULT_WRITE_BYTES=" + std::to_string(budget) + " CI=true " +
                       LsdsBinary() + " merge " + Path("s0").string() + " " + Path("s1").string() +
                       " " + Path("s2").string() + " -o " + Path("full").string());
    EXPECT_EQ(r.exit_code, 2) << budget << ": " << r.output;
    EXPECT_NE(r.output.find("error: " + Path("full").string() + "/"), std::string::npos)
        << budget << ": " << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos)
        << budget << ": " << r.output;
    EXPECT_EQ(r.output.find("already committed"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("lsds-tmp"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(Path("full")));
  }
  for (const auto& entry : fs::directory_iterator(dir_->path()))
    EXPECT_EQ(entry.path().filename().string().find("lsds-tmp"), std::string::npos) << entry.path();
}

// Every value the tasks pass to lsds generate is checked by generate's own
// checks before a script is written; every value in an #SBATCH line must
// keep to its line.
TEST_F(MergeCliTest, SubmitRefusesValuesEveryTaskWouldFailOn) {
  const std::string submit = "CI=true " + LsdsBinary() + " submit slurm " +
                             ::lsds::testing::SourceDir() + "/examples/uav_survey.lscene " +
                             Path("small.lcap").string() + " --shards 3 -o " +
                             Path("bad_submit").string() + " ";
  const std::pair<std::string, std::string> cases[] = {
      {"--depth sideways", "--depth sideways: expected planar or perspective"},
      {"--spp 3", "--spp 3: samples per pixel must be a square number"},
      {"--spp 0", "--spp 0: samples per pixel must be a square number"},
      {"--mem $'8G\\r'", "--mem '8G\\x0D': control characters"},
      {"--time $'1:00:00\\r'", "--time '1:00:00\\x0D': control characters"},
      {"--partition $'cpu\\x01'", "--partition 'cpu\\x01': control characters"},
      {"--account $'a\\tb'", "--account 'a\\x09b': control characters"},
  };
  for (const auto& [flags, message] : cases) {
    const testing::CommandResult r = RunCommandLine("bash -c \"" + submit + flags + "\"");
    EXPECT_EQ(r.exit_code, 2) << flags << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << flags << ": " << r.output;
    EXPECT_FALSE(fs::exists(Path("bad_submit.shards"))) << flags;
  }
}

// The scripts of `lsds submit slurm` run without Slurm: bash ignores the
// #SBATCH lines, so running each array task by hand and then the merge must
// give the single run.
TEST_F(MergeCliTest, SubmitScriptsRunByHandGiveTheSingleRun) {
  const std::string submit = "CI=true " + LsdsBinary() + " submit slurm " +
                             ::lsds::testing::SourceDir() + "/examples/uav_survey.lscene " +
                             Path("small.lcap").string() + " --spp 1 --seed 3 -o " +
                             Path("slurm_run").string();
  testing::CommandResult r = RunCommandLine(submit + " --shards 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path work = Path("slurm_run.shards");
  for (const char* script : {"generate.sbatch", "merge.sbatch", "submit.sh"})
    EXPECT_TRUE(fs::is_regular_file(work / script)) << script;
  for (int task = 0; task < 3; ++task) {
    r = RunCommandLine("SLURM_ARRAY_TASK_ID=" + std::to_string(task) + " bash " +
                       (work / "generate.sbatch").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // A task run again (a requeue) keeps its shard: --resume.
  r = RunCommandLine("SLURM_ARRAY_TASK_ID=1 bash " + (work / "generate.sbatch").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommandLine("bash " + (work / "merge.sbatch").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The tasks run lsds generate with its default layouts.
  ASSERT_EQ(Generate("whole_default", "", 3, ""), 0);
  EXPECT_EQ(Tree(Path("slurm_run")), Tree(Path("whole_default")));

  // The same run again needs no --force; another run in the same folder does.
  fs::remove_all(Path("slurm_run"));
  r = RunCommandLine(submit + " --shards 3");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = RunCommandLine(submit + " --shards 4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  // More shards than frames: a task would have nothing to render.
  r = RunCommandLine(submit + " --shards 13 --work-dir " + Path("too_many").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("the run has 12 frames"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("too_many")));
  // --submit where there is no Slurm.
  r = RunCommandLine("PATH=/nonexistent " + submit + " --shards 3 --submit");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("sbatch not found"), std::string::npos) << r.output;
  r = RunCommandLine(submit + " --shards 3 --scheduler-typo 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

// `lsds submit --compact`: every task renders with generate --compact, so the merged run equals
// the single compact run ("whole") byte for byte.
TEST_F(MergeCliTest, SubmitCompactGivesTheSingleCompactRun) {
  const fs::path work = Path("compact_run.shards");
  testing::CommandResult r =
      RunCommandLine("CI=true " + LsdsBinary() + " submit slurm " + ::lsds::testing::SourceDir() +
                     "/examples/uav_survey.lscene " + Path("small.lcap").string() +
                     " --spp 1 --seed 3 --compact --shards 3 -o " + Path("compact_run").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(Slurp(work / "generate.sbatch").find(" --compact "), std::string::npos);
  for (int task = 0; task < 3; ++task) {
    r = RunCommandLine("SLURM_ARRAY_TASK_ID=" + std::to_string(task) + " bash " +
                       (work / "generate.sbatch").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  r = RunCommandLine("bash " + (work / "merge.sbatch").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // "whole" is the single run of generate --compact (Generate's default layouts).
  EXPECT_EQ(Tree(Path("compact_run")), Tree(Path("whole")));
}

}  // namespace
}  // namespace lsds
