// lsds import bop: a BlenderProc BOP scene synthesized from an analytic scene
// (bop_fixture.h) imports into a collection whose truth equals the scene's
// known truth, validates clean and converts to COCO masks equal to the
// fixture's visible masks.
#include <cmath>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "importers/import_collection.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "tests/import/bop_fixture.h"
#include "tests/import/import_checks.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class BopImportTest : public ::testing::Test {
 protected:
  TempDir dir_;
  synth::Spec spec_ = ObliqueImportSpec();
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
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    // Pixel-centre cx, cy + 0.5: the edge-convention intrinsics exactly.
    EXPECT_EQ(frame.camera.intrinsics, truth.truth.camera.intrinsics);
    EXPECT_EQ(frame.camera.cam_from_world_rotation, truth.truth.camera.cam_from_world_rotation);
    EXPECT_LT(
        (frame.camera.cam_from_world_translation - truth.truth.camera.cam_from_world_translation)
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
      EXPECT_LT((got.obb.world_from_box - want.obb.world_from_box).cwiseAbs().maxCoeff(), 1e-12);
    }
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, TargetIds(truth));
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
        EXPECT_NEAR(
            position.Get(c).floats[p], want_position.Get(c).floats[p], 0.5e-3 + 1e-6 * want[p]);
    }
    if (k == frames.size() - 1) {
      EXPECT_GT(beyond, 0);
    }
  }
}

TEST_F(BopImportTest, ValidatesCleanAndConvertsToCocoMasksOfTheVisibleMasks) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  ExpectImportValidatesAndConverts(
      "bop", scene, dir_.path(), spec_.width, spec_.height, [&](int k) {
        return TargetIds(synth::RenderFrame(spec_, k));
      });
}

TEST_F(BopImportTest, ASourceThatIsNotWhatItClaimsGivesALocatedError) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  json gt = json::parse(ReadText(scene / "scene_gt.json"));
  gt["2"][1]["obj_id"] = 9;
  std::ofstream(scene / "scene_gt.json") << gt.dump();
  const CommandResult result = RunCommandLine(LsdsBinary() + " import bop " + scene.string() +
                                              " -o " + (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("scene_gt.json#/2/1/obj_id"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
}  // namespace lsds::testing
