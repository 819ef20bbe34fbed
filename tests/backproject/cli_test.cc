// End to end: the lsds binary, its exit codes, messages, and no partial outputs
// on errors.
#include <fstream>

#include <gtest/gtest.h>

#include "backproject/cloud_io.h"
#include "backproject/cloud_io_abi.h"
#include "tests/backproject/test_util.h"

namespace lsds::pointcloud {
namespace {

namespace fs = std::filesystem;
using testing::ListDir;
using testing::RunLsds;
using testing::ScratchDir;

class BackprojectCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new ScratchDir("cli");
    testing::WriteSynth(*dir_ / "c", synth::DefaultSpec());
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path Collection() { return *dir_ / "c"; }
  static ScratchDir* dir_;
};
ScratchDir* BackprojectCli::dir_ = nullptr;

TEST_F(BackprojectCli, WritesPerFrameFusedAndChecks) {
  ScratchDir out("cli_out");
  std::string log;
  ASSERT_EQ(RunLsds("backproject " + Collection().string() + " -o " + (out / "frames").string() +
                        " --format ply --normals --check --tolerance 1e-4",
                    &log),
            0)
      << log;
  EXPECT_EQ(ListDir(out / "frames"), "000000.ply 000001.ply 000002.ply 000003.ply ");
  EXPECT_NE(log.find("max_error"), std::string::npos) << log;
  EXPECT_NE(log.find("all"), std::string::npos) << log;
  ASSERT_EQ(RunLsds("backproject " + Collection().string() + " --fuse --voxel 0.2 -o " +
                        (out / "fused.pcd").string(),
                    &log),
            0)
      << log;
  EXPECT_GT(ReadCloud(out / "fused.pcd").points.size(), 100u);
  // Refuses to overwrite without --force; replaces with it.
  EXPECT_EQ(
      RunLsds("backproject " + Collection().string() + " --fuse -o " + (out / "fused.pcd").string(),
              &log),
      2);
  EXPECT_NE(log.find("--force"), std::string::npos) << log;
  EXPECT_EQ(RunLsds("backproject " + Collection().string() + " --fuse --force -o " +
                        (out / "fused.pcd").string(),
                    &log),
            0)
      << log;
  EXPECT_EQ(ListDir(out.path()), "frames fused.pcd ");
  // A perturbed-pose tolerance breach is a finding: exit 1.
  EXPECT_EQ(RunLsds("backproject " + Collection().string() + " --check --tolerance 0", &log), 1)
      << log;
}

TEST_F(BackprojectCli, CollectionWithoutDepthIsAClearError) {
  ScratchDir dir("cli_nodepth");
  synth::Spec spec = synth::DefaultSpec();
  spec.layers = {"rgb", "classid", "instanceid"};
  testing::WriteSynth(dir / "c", spec);
  std::string log;
  EXPECT_EQ(
      RunLsds("backproject " + (dir / "c").string() + " --fuse -o " + (dir / "x.pcd").string(),
              &log),
      2);
  EXPECT_NE(log.find("no flat depth layer"), std::string::npos) << log;
  EXPECT_NE(log.find("collection.json"), std::string::npos) << log;
  EXPECT_EQ(ListDir(dir.path()), "c ");
}

TEST_F(BackprojectCli, UnknownExtensionIsAClearError) {
  ScratchDir dir("cli_ext");
  std::string log;
  EXPECT_EQ(
      RunLsds("backproject " + Collection().string() + " --fuse -o " + (dir / "x.xyz").string(),
              &log),
      2);
  EXPECT_NE(log.find("unknown point cloud extension '.xyz'"), std::string::npos) << log;
  // Per-frame output is a folder: a .pcd name without --fuse is refused rather
  // than guessed.
  EXPECT_EQ(
      RunLsds("backproject " + Collection().string() + " -o " + (dir / "x.pcd").string(), &log), 2);
  EXPECT_NE(log.find("--fuse"), std::string::npos) << log;
  EXPECT_EQ(ListDir(dir.path()), "");
}

TEST_F(BackprojectCli, UnwritableOutputIsAClearError) {
  ScratchDir dir("cli_unwritable");
  std::string log;
  EXPECT_EQ(RunLsds("backproject " + Collection().string() + " --fuse -o " +
                        (dir / "no/such/x.pcd").string(),
                    &log),
            2);
  EXPECT_NE(log.find("does not exist"), std::string::npos) << log;
  // The parent "folder" is a file.
  std::ofstream(dir / "file").put('x');
  EXPECT_EQ(
      RunLsds("backproject " + Collection().string() + " -o " + (dir / "file" / "frames").string(),
              &log),
      2);
  EXPECT_EQ(ListDir(dir.path()), "file ");
}

TEST_F(BackprojectCli, AnErrorMidwayLeavesNothingBehind) {
  ScratchDir dir("cli_midway");
  synth::Spec spec = synth::DefaultSpec();
  testing::WriteSynth(dir / "c", spec);
  fs::remove(dir / "c" / "depth" / "000002.exr");
  fs::create_directory(dir / "out");
  std::string log;
  EXPECT_EQ(
      RunLsds("backproject " + (dir / "c").string() + " -o " + (dir / "out" / "frames").string(),
              &log),
      2);
  EXPECT_NE(log.find("000002.exr"), std::string::npos) << log;
  EXPECT_EQ(RunLsds("backproject " + (dir / "c").string() + " --fuse -o " +
                        (dir / "out" / "f.ply").string(),
                    &log),
            2);
  EXPECT_EQ(ListDir(dir / "out"), "");
}

// PCL is a plug-in (cloud_io_abi.h): one that does not load stops the command with exit code 2,
// the plug-in's path and the loader's reason, and nothing written.
TEST_F(BackprojectCli, ABrokenCloudPlugInIsAnErrorNotACrash) {
  ScratchDir dir("cli_plugin");
  fs::create_directory(dir / "plugins");
  std::ofstream((dir / "plugins" / kCloudIoPlugin).string()) << "not a shared library\n";
  fs::create_directory(dir / "out");
  std::string log;
  // NOLINTNEXTLINE(concurrency-mt-unsafe): the tests of this binary run on one thread
  setenv("LSDS_PLUGIN_DIR", (dir / "plugins").c_str(), 1);
  const int code = RunLsds(
      "backproject " + Collection().string() + " --fuse -o " + (dir / "out" / "f.ply").string(),
      &log);
  unsetenv("LSDS_PLUGIN_DIR");  // NOLINT(concurrency-mt-unsafe)
  EXPECT_EQ(code, 2) << log;
  EXPECT_NE(log.find("cannot load the plug-in " + (dir / "plugins" / kCloudIoPlugin).string()),
            std::string::npos)
      << log;
  EXPECT_EQ(ListDir(dir / "out"), "");
}

}  // namespace
}  // namespace lsds::pointcloud
