// GenerateCollection end to end: complete collections that read back, atomic
// refusal, determinism,
// --frames, --shard byte-identical to a single run, --resume, and the `lsds
// generate` command.
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "generator/generate.h"
#include "generator/plan/plan_json.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/json_io.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"
#include "tests/generator/test_plans.h"
#include "tests/test_util.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

Plan MovingPlan(int frames = 4) {
  Plan plan = testing::FlatPlan(32, 24);
  plan.objects.push_back(testing::Box("B1", 1, {0, 0, 1}, {2, 2, 2}));
  plan.objects.push_back(testing::Box("B2", 2, {3, 1, 0.5}, {1, 1, 1}));
  plan.objects.back().class_name = "barrel";
  const PlannedFrame first = plan.frames[0];
  plan.frames.clear();
  for (int f = 0; f < frames; ++f) {
    PlannedFrame frame = first;
    frame.index = f;
    frame.time = 0.1 * f;
    frame.cam_from_world = testing::Nadir({0.5 * f - 1, 0, 15});
    plan.frames.push_back(frame);
  }
  return plan;
}

// A path that does not exist yet, in a folder removed when the test process ends.
fs::path TempRoot(const std::string& name) {
  static const lsds::testing::TempDir process_dir;
  return process_dir / name;
}

GenerateOptions Options(const fs::path& root) {
  GenerateOptions options;
  options.output = root;
  options.progress = false;
  options.threads = 2;
  return options;
}

std::map<int64_t, Frame> FramesByIndex(const fs::path& root) {
  std::map<int64_t, Frame> frames;
  CollectionReader(root).ForEachFrame([&](const Frame& f) { frames[f.index] = f; });
  return frames;
}

TEST(GenerateCollection, WritesACompleteCollectionThatReadsBack) {
  const fs::path root = TempRoot("complete");
  const GenerateSummary summary = GenerateCollection(MovingPlan(), Options(root));
  EXPECT_EQ(summary.frames_rendered, 4);
  EXPECT_GT(summary.rays, 0u);
  // The steady state leaves out the first render and the last write.
  EXPECT_GT(summary.steady_seconds_per_frame, 0);
  EXPECT_LT(summary.steady_seconds_per_frame * 3, summary.total_seconds);
  const CollectionReader reader(root);
  EXPECT_EQ(reader.header().frame_count, 4);
  EXPECT_EQ(reader.header().layers.size(), StandardLayerSemantics().size());
  EXPECT_EQ(*reader.header().provenance.seed, 7u);
  EXPECT_EQ(reader.header().provenance.render["samples_per_pixel"], 4);
  EXPECT_FALSE(fs::exists(root / ".lsds-generate"));
  EXPECT_TRUE(fs::exists(root / kMetadataFile));
  reader.ForEachFrame([&](const Frame& frame) {
    EXPECT_EQ(frame.files.size(), StandardLayerSemantics().size());
    for (const auto& [layer, file] : frame.files) {
      EXPECT_TRUE(fs::exists(root / file)) << file;
      // Every layer carries the frame's camera in its header.
      const exr::ExrInfo info = exr::ReadExrInfo(root / file);
      ASSERT_TRUE(info.camera) << file;
      EXPECT_TRUE(
          info.camera->cam_from_world.isApprox(HeaderCameraOf(frame.camera).cam_from_world, 1e-6))
          << file;
    }
    ASSERT_EQ(frame.objects.size(), 2u);
    // The truth agrees with the instance layer on disk.
    const exr::FlatImage ids = exr::ReadFlatExr(reader.LayerPath(frame, "instanceid"));
    for (const ObjectTruth& o : frame.objects) {
      int64_t count = 0;
      for (uint32_t id : ids.Get("id").uints) count += id == o.instance_id;
      EXPECT_EQ(count, o.visible_pixels);
      EXPECT_GT(o.visible_pixels, 0);
    }
  });
  MetadataReader metadata(root / kMetadataFile);
  EXPECT_EQ(metadata.header().frame_count, 4);
}

TEST(GenerateCollection, RefusesAnExistingOutputWithoutForce) {
  const fs::path root = TempRoot("refuse");
  Plan plan = MovingPlan(1);
  GenerateCollection(plan, Options(root));
  EXPECT_THROW(GenerateCollection(plan, Options(root)), Error);
  GenerateOptions force = Options(root);
  force.force = true;
  EXPECT_EQ(GenerateCollection(plan, force).frames_rendered, 1);
  // --force never deletes a folder that is not a collection.
  const fs::path other = TempRoot("not_a_collection");
  fs::create_directories(other);
  WriteFileAtomic(other / "precious.txt", "keep me");
  force.output = other;
  EXPECT_THROW(GenerateCollection(plan, force), Error);
  EXPECT_TRUE(fs::exists(other / "precious.txt"));
}

TEST(GenerateCollection, RejectsBadOptionsAndPlansBeforeWriting) {
  const fs::path root = TempRoot("bad");
  GenerateOptions options = Options(root);
  options.spp = 3;
  EXPECT_THROW(GenerateCollection(MovingPlan(1), options), Error);
  options = Options(root);
  options.shard_index = 2;
  options.shard_count = 2;
  EXPECT_THROW(GenerateCollection(MovingPlan(1), options), Error);
  Plan plan = MovingPlan(1);
  plan.objects[0].class_name = "cubee";
  EXPECT_THROW(GenerateCollection(plan, Options(root)), Error);
  EXPECT_FALSE(fs::exists(root));
}

// Every file of `a` equals the file of the same name in `b`, byte for byte.
void ExpectSameFrameFiles(const fs::path& a, const fs::path& b, const Frame& frame) {
  for (const auto& [layer, file] : frame.files) {
    EXPECT_EQ(ReadFile(a / file), ReadFile(b / file)) << file;
  }
}

TEST(GenerateCollection, SameSeedGivesByteIdenticalOutput) {
  const fs::path a = TempRoot("det_a"), b = TempRoot("det_b");
  GenerateCollection(MovingPlan(), Options(a));
  GenerateOptions one_thread = Options(b);
  one_thread.threads = 1;
  GenerateCollection(MovingPlan(), one_thread);
  EXPECT_EQ(ReadFile(a / kCollectionFile), ReadFile(b / kCollectionFile));
  EXPECT_EQ(ReadFile(a / kMetadataFile), ReadFile(b / kMetadataFile));
  for (const auto& [index, frame] : FramesByIndex(a)) ExpectSameFrameFiles(a, b, frame);
}

TEST(GenerateCollection, ShardsAndFrameRangesEqualTheSingleRun) {
  const fs::path single = TempRoot("single");
  GenerateCollection(MovingPlan(5), Options(single));
  const std::map<int64_t, Frame> all = FramesByIndex(single);
  std::set<int64_t> covered;
  for (int shard = 0; shard < 2; ++shard) {
    const fs::path root = TempRoot("shard" + std::to_string(shard));
    GenerateOptions options = Options(root);
    options.shard_index = shard;
    options.shard_count = 2;
    GenerateCollection(MovingPlan(5), options);
    for (const auto& [index, frame] : FramesByIndex(root)) {
      EXPECT_EQ(index % 2, shard);
      covered.insert(index);
      EXPECT_EQ(FrameToJson(frame).dump(), FrameToJson(all.at(index)).dump());
      ExpectSameFrameFiles(root, single, frame);
    }
  }
  EXPECT_EQ(covered.size(), 5u);
  const fs::path range = TempRoot("range");
  GenerateOptions options = Options(range);
  options.frames = FrameRange{2, 4};
  GenerateCollection(MovingPlan(5), options);
  const std::map<int64_t, Frame> part = FramesByIndex(range);
  ASSERT_EQ(part.size(), 2u);
  for (const auto& [index, frame] : part) {
    EXPECT_EQ(FrameToJson(frame).dump(), FrameToJson(all.at(index)).dump());
    ExpectSameFrameFiles(range, single, frame);  // motion of frame 2 still comes from frame 1
  }
}

TEST(GenerateCollection, ResumeRendersOnlyMissingFrames) {
  const fs::path root = TempRoot("resume"), reference = TempRoot("resume_ref");
  GenerateCollection(MovingPlan(), Options(reference));
  GenerateCollection(MovingPlan(), Options(root));
  fs::remove(root / "depth" / "000002.exr");
  GenerateOptions resume = Options(root);
  resume.resume = true;
  const GenerateSummary summary = GenerateCollection(MovingPlan(), resume);
  EXPECT_EQ(summary.frames_rendered, 1);
  EXPECT_EQ(summary.frames_skipped, 3);
  EXPECT_EQ(summary.steady_seconds_per_frame, 0);  // one frame: no steady state
  EXPECT_EQ(ReadFile(root / kCollectionFile), ReadFile(reference / kCollectionFile));
  for (const auto& [index, frame] : FramesByIndex(root))
    ExpectSameFrameFiles(root, reference, frame);
  // Other settings are refused rather than mixed into the collection.
  resume.spp = 9;
  fs::remove(root / "depth" / "000002.exr");
  EXPECT_THROW(GenerateCollection(MovingPlan(), resume), Error);
}

int Shell(const std::string& command) {
  const int status = std::system((command + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(GenerateCommand, DemoCollectionPassesInfoAndRefusesOverwrite) {
  const std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  const fs::path root = TempRoot("cli");
  const std::string generate =
      lsds + " generate --demo --demo-frames 2 --demo-size 48x32 --spp 1 -q -o " + root.string();
  ASSERT_EQ(Shell(generate), 0);
  EXPECT_EQ(Shell(generate), 2);  // exists, no --force
  EXPECT_EQ(Shell(generate + " --force"), 0);
  EXPECT_EQ(Shell(lsds + " info " + root.string()), 0);
  EXPECT_EQ(Shell(lsds + " generate --demo --spp 3 -q --force -o " + root.string()), 2);
  EXPECT_EQ(Shell(lsds + " generate -q -o " + root.string()), 2);  // no scene
  if (Shell("command -v exrheader") == 0) {
    EXPECT_EQ(Shell("exrheader " + (root / "bundle" / "000001.exr").string()), 0);
    EXPECT_EQ(Shell("exrheader " + (root / "rgb" / "000000.exr").string()), 0);
  }
}

TEST(GenerateCommand, PlanJsonRendersLikeThePlanInMemory) {
  const fs::path reference = TempRoot("plan_ref"), root = TempRoot("plan_cli");
  const fs::path plan_file = TempRoot("plan.json");
  const Plan plan = MovingPlan(3);
  WriteFileAtomic(plan_file, PlanToJson(plan).dump(2));
  GenerateCollection(plan, Options(reference));
  const std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  ASSERT_EQ(Shell(lsds + " generate -q --plan " + plan_file.string() + " -o " + root.string()), 0);
  EXPECT_EQ(ReadFile(root / kCollectionFile), ReadFile(reference / kCollectionFile));
  for (const auto& [index, frame] : FramesByIndex(root))
    ExpectSameFrameFiles(root, reference, frame);
}

TEST(GenerateCommand, RendersAnLsceneExample) {
  const fs::path root = TempRoot("lscene");
  const std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  const std::string scene = ::lsds::testing::ExamplesDir() + "/rocky_sand_clutter.lscene";
  ASSERT_EQ(Shell(lsds + " generate -q --spp 1 --seed 3 " + scene + " -o " + root.string()), 0);
  const std::map<int64_t, Frame> frames = FramesByIndex(root);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_FALSE(frames.begin()->second.objects.empty());
  EXPECT_EQ(Shell(lsds + " generate -q --force " + scene + "x -o " + root.string()),
            2);  // unreadable
}

// Embree, assimp, Ceres, OpenCV's image codecs and PCL are plug-ins (docs/architecture.md,
// "Plug-ins"): with every one of them broken, `--version` and `info` still work (nothing loads
// them at start-up), and generate and export-scene, which need Embree and assimp, stop with exit
// code 2 and the plug-in's path before writing anything.
TEST(GenerateCommand, PlugInsAreOpenedOnlyByTheCommandsThatNeedThem) {
  const fs::path root = TempRoot("broken_plugins");
  const fs::path plugins = root / "plugins";
  fs::create_directories(plugins);
  for (const char* name : {"lsds_embree.so",
                           "lsds_mesh_io.so",
                           "lsds_camera_solver.so",
                           "lsds_image_codecs.so",
                           "lsds_cloud_io.so"})
    std::ofstream((plugins / name).string()) << "not a shared library\n";
  const std::string with_broken_plugins =
      "LSDS_PLUGIN_DIR=" + plugins.string() + " " + ::lsds::testing::LsdsBinary() + " ";
  const fs::path collection = root / "demo";
  ASSERT_EQ(::lsds::testing::RunLsds("generate --demo --demo-frames 1 --demo-size 16x12 --spp 1 "
                                     "-q -o " +
                                     collection.string())
                .exit_code,
            0);
  EXPECT_EQ(::lsds::testing::RunCommandLine(with_broken_plugins + "--version").exit_code, 0);
  const ::lsds::testing::CommandResult info =
      ::lsds::testing::RunCommandLine(with_broken_plugins + "info " + collection.string());
  EXPECT_EQ(info.exit_code, 0) << info.output;

  const ::lsds::testing::CommandResult generate = ::lsds::testing::RunCommandLine(
      with_broken_plugins + "generate --demo --demo-frames 1 --demo-size 16x12 --spp 1 -q -o " +
      (root / "out").string());
  EXPECT_EQ(generate.exit_code, 2) << generate.output;
  EXPECT_NE(
      generate.output.find("cannot load the plug-in " + (plugins / "lsds_embree.so").string()),
      std::string::npos)
      << generate.output;
  EXPECT_FALSE(fs::exists(root / "out"));

  const std::string examples = ::lsds::testing::ExamplesDir();
  const ::lsds::testing::CommandResult export_scene = ::lsds::testing::RunCommandLine(
      with_broken_plugins + "export-scene -q " + examples + "/uav_survey.lscene " + examples +
      "/uav_survey.lcap --frames 0:1 -o " + (root / "scene").string());
  EXPECT_EQ(export_scene.exit_code, 2) << export_scene.output;
  EXPECT_NE(
      export_scene.output.find("cannot load the plug-in " + (plugins / "lsds_mesh_io.so").string()),
      std::string::npos)
      << export_scene.output;
  EXPECT_FALSE(fs::exists(root / "scene"));
}

// 60 trees of about 12,000 triangles each need about 190 MiB of scene: over a 150 MiB budget (the
// default frame film takes 112) that is a usage error naming the scene before anything is written.
TEST(GenerateCommand, ASceneOverTheMemoryBudgetFailsBeforeAnyOutput) {
  const fs::path root = TempRoot("scene_budget");
  fs::create_directories(root);
  const fs::path scene = root / "trees.lscene";
  std::ofstream(scene) << "LSCENE = ONE(W) MANY(T, 60)\n"
                          "W = terrain{size:[200,200]}\n"
                          "T = object{class:tree,position:{ON:W},on_overlap:delete}\n";
  const ::lsds::testing::CommandResult result =
      ::lsds::testing::RunLsds("generate -q --spp 1 --memory-budget 150M " + scene.string() +
                               " -o " + (root / "out").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("the render scene of 60 objects needs"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("memory budget"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(root / "out"));
}

}  // namespace
}  // namespace lsds::gen
