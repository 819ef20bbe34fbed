// lsds import bop: a BlenderProc BOP scene synthesized from an analytic scene
// (bop_fixture.h) imports into a collection whose truth equals the scene's
// known truth, validates clean and converts to COCO masks equal to the
// fixture's visible masks.
#include <cmath>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/importers/import_collection.h"
#include "libs/util/error.h"
#include "tests/convert/reference_decoders.h"
#include "tests/import/bop_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

synth::Spec FixtureSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.samples_per_axis = 1;
  const Rigid3d look = LookAt({-14, -9, 6}, {0, 0, 1});
  const Eigen::Quaterniond roll(
      Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  spec.cam_from_world.push_back(Rigid3d(roll, Eigen::Vector3d::Zero()) * look);
  return spec;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The fixture's id layer: the boxes' instances (BOP masks only its objects;
// the ground is background).
std::vector<uint32_t> MaskedIds(const synth::RenderedFrame& truth) {
  std::vector<uint32_t> ids = truth.flat.at("instanceid").Get("id").uints;
  for (uint32_t& id : ids)
    if (id == 1000) id = 0;
  return ids;
}

class BopImportTest : public ::testing::Test {
 protected:
  TempDir dir_;
  synth::Spec spec_ = FixtureSpec();
};

TEST_F(BopImportTest, TruthEqualsTheAnalyticScene) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  const fs::path out = dir_ / "collection";
  import::ImportCollection("bop", scene, out, {}, false);
  const CollectionReader reader(out);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth =
        synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    // Pixel-centre cx, cy + 0.5: the edge-convention intrinsics exactly.
    EXPECT_EQ(frame.camera.intrinsics, truth.truth.camera.intrinsics);
    EXPECT_EQ(frame.camera.cam_from_world_rotation,
              truth.truth.camera.cam_from_world_rotation);
    EXPECT_LT((frame.camera.cam_from_world_translation -
               truth.truth.camera.cam_from_world_translation)
                  .norm(),
              1e-12);
    ASSERT_EQ(frame.objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      const ObjectTruth& got = frame.objects[i];
      const ObjectTruth& want = truth.truth.objects[i];
      EXPECT_EQ(got.instance_id, want.instance_id);
      EXPECT_EQ(got.bbox, want.bbox);  // exact
      EXPECT_EQ(got.visible_pixels, want.visible_pixels);
      EXPECT_NEAR(got.visibility, want.visibility, 1e-12);
      EXPECT_NEAR(got.in_frame, want.in_frame, 1e-9);
      EXPECT_LT((got.obb.center - want.obb.center).norm(), 1e-9);
      EXPECT_LT((got.obb.half_extents - want.obb.half_extents).norm(), 1e-12);
      EXPECT_LT((got.obb.world_from_box - want.obb.world_from_box)
                    .cwiseAbs()
                    .maxCoeff(),
                1e-12);
    }
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, MaskedIds(truth));
    // Depth: 16-bit units of 0.5 mm, so within 0.25 mm; beyond 32.77 m the
    // PNG holds 0 (none), read as +inf.
    const std::vector<float> depth = read("depth").Get("Z").floats;
    const std::vector<float>& want = truth.flat.at("depth").Get("Z").floats;
    const exr::FlatImage position = read("worldposition");
    const exr::FlatImage& want_position = truth.flat.at("worldposition");
    int beyond = 0;
    for (size_t p = 0; p < depth.size(); ++p) {
      if (!(want[p] * 1000 / kBopDepthScale <= 65535.4)) {
        EXPECT_TRUE(std::isinf(depth[p]));
        ++beyond;
        continue;
      }
      EXPECT_NEAR(depth[p], want[p], 0.25e-3 + 1e-6 * want[p]);
      for (const char* c : {"X", "Y", "Z"})
        EXPECT_NEAR(position.Get(c).floats[p],
                    want_position.Get(c).floats[p],
                    0.5e-3 + 1e-6 * want[p]);
    }
    if (k == frames.size() - 1) EXPECT_GT(beyond, 0);
  }
}

TEST_F(BopImportTest, ValidatesCleanAndConvertsToCocoMasksOfTheVisibleMasks) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  const fs::path out = dir_ / "collection";
  const CommandResult imported = RunCommandLine(
      LsdsBinary() + " import bop " + scene.string() + " -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  const CommandResult validate = RunCommandLine(
      LsdsBinary() + " validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  const fs::path coco = dir_ / "coco";
  const CommandResult convert =
      RunCommandLine(LsdsBinary() + " convert " + out.string() +
                     " --to coco --images none -o " + coco.string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  fs::path annotations;
  for (const auto& entry : fs::recursive_directory_iterator(coco))
    if (entry.path().extension() == ".json" &&
        entry.path().filename().string().rfind("instances", 0) == 0)
      annotations = entry.path();
  ASSERT_FALSE(annotations.empty());
  const json doc = json::parse(ReadText(annotations));
  std::map<int64_t, std::string> image_names;
  for (const json& image : doc["images"])
    image_names[image["id"].get<int64_t>()] = image["file_name"];
  ASSERT_GT(doc["annotations"].size(), 0u);
  const int w = spec_.width, h = spec_.height;
  for (const json& a : doc["annotations"]) {
    const int k = std::stoi(
        fs::path(image_names.at(a["image_id"].get<int64_t>())).stem().string());
    const std::vector<uint32_t> ids = MaskedIds(synth::RenderFrame(spec_, k));
    const uint32_t instance = a["lsds"]["instance_id"];
    int64_t total = 0;
    const cv::Mat mask = CocoDecode(
        CocoCountsFromString(a["segmentation"]["counts"]), h, w, &total);
    int64_t differing = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        differing += (mask.at<uint8_t>(j, i) != 0) !=
                     (ids[static_cast<size_t>(j) * w + i] == instance);
    EXPECT_EQ(differing, 0) << "instance " << instance << " frame " << k;
  }
}

TEST_F(BopImportTest, ASourceThatIsNotWhatItClaimsGivesALocatedError) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  json gt = json::parse(ReadText(scene / "scene_gt.json"));
  gt["2"][1]["obj_id"] = 9;
  std::ofstream(scene / "scene_gt.json") << gt.dump();
  const CommandResult result =
      RunCommandLine(LsdsBinary() + " import bop " + scene.string() + " -o " +
                     (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("scene_gt.json#/2/1/obj_id"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
}  // namespace lsds::testing
