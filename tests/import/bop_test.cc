// lsds import bop: a BlenderProc BOP scene synthesized from an analytic scene
// (bop_fixture.h) imports into a collection whose truth equals the scene's
// known truth, validates clean and converts to COCO masks equal to the
// fixture's visible masks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

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

// The gt indices whose visible mask holds each pixel of image k.
std::vector<std::vector<uint32_t>> MaskClaims(const fs::path& scene,
                                              const synth::Spec& spec,
                                              int k) {
  std::vector<std::vector<uint32_t>> claims(static_cast<size_t>(spec.width) * spec.height);
  for (size_t g = 0; g < spec.boxes.size(); ++g) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d_%06d.png", k, static_cast<int>(g));
    const cv::Mat mask = cv::imread((scene / "mask_visib" / name).string(), cv::IMREAD_GRAYSCALE);
    for (int j = 0; j < spec.height; ++j)
      for (int i = 0; i < spec.width; ++i)
        if (mask.at<uint8_t>(j, i) != 0)
          claims[static_cast<size_t>(j) * spec.width + i].push_back(static_cast<uint32_t>(g));
  }
  return claims;
}

// What the importer's instance layer must hold for BlenderProc's masks: the
// one object of a pixel one mask claims, the renderer's front object where
// several do (the depth shows it), 0 where none does.
std::vector<uint32_t> ImportedIdsOfBlenderProcMasks(const fs::path& scene,
                                                    const synth::Spec& spec,
                                                    int k) {
  const std::vector<std::vector<uint32_t>> claims = MaskClaims(scene, spec, k);
  const std::vector<uint32_t> front = TargetIds(synth::RenderFrame(spec, k));
  std::vector<uint32_t> ids(claims.size(), 0);
  for (size_t p = 0; p < ids.size(); ++p)
    if (claims[p].size() == 1)
      ids[p] = spec.boxes[claims[p][0]].instance_id;
    else if (claims[p].size() > 1)
      ids[p] = front[p];
  return ids;
}

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
      EXPECT_LT((got.obb->center - want.obb->center).norm(), 1e-9);
      EXPECT_LT((got.obb->half_extents - want.obb->half_extents).norm(), 1e-12);
      EXPECT_LT((got.obb->world_from_box - want.obb->world_from_box).cwiseAbs().maxCoeff(), 1e-12);
    }
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, TargetIds(truth));
    // Depth: 16-bit units of 0.5 mm, so within 0.25 mm; the sky and beyond
    // 32.77 m the PNG holds BlenderProc's clip 65535, read as +inf.
    const std::vector<float> depth = read("depth").Get("Z").floats;
    const std::vector<float>& want = truth.flat.at("depth").Get("Z").floats;
    // Read through the collection's reader: X, Y, Z whatever the layer's layout.
    const exr::FlatImage position = reader.ReadFlatLayer(frame, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage& want_position = truth.flat.at("worldposition");
    int beyond = 0;
    for (size_t p = 0; p < depth.size(); ++p) {
      if (!(want[p] * 1000 / kBopDepthScale < 65534.5)) {
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

// Objects at BOP's scale (centimetres, a camera half a metre away) that touch:
// a cube on the ground, a smaller one on top of it, a slab against its side.
synth::Spec TouchingObjectsSpec() {
  synth::Spec spec;
  spec.width = 320, spec.height = 240, spec.samples_per_axis = 1;
  spec.classes = {{1, "ground"}, {2, "box"}, {3, "crate"}};
  synth::Box cube, top, slab;
  cube.instance_id = 1, cube.name = "cube";
  cube.center = {0, 0, 0.03}, cube.half_extents = {0.03, 0.03, 0.03};
  top.instance_id = 2, top.name = "top";
  top.center = {0.01, 0, 0.08}, top.half_extents = {0.02, 0.02, 0.02}, top.yaw_deg = 20;
  slab.class_id = 3, slab.instance_id = 3, slab.name = "slab";
  slab.center = {0.07, 0, 0.025}, slab.half_extents = {0.04, 0.03, 0.025};
  spec.boxes = {cube, top, slab};
  spec.cam_from_world = {LookAt({0.35, -0.3, 0.25}, {0.02, 0, 0.04}),
                         LookAt({-0.2, -0.35, 0.3}, {0.02, 0, 0.04})};
  return spec;
}

TEST_F(BopImportTest, BlenderProcsOverlappingMasksGoToTheObjectTheDepthShows) {
  const synth::Spec spec = TouchingObjectsSpec();
  // BlenderProc's default delta (write_bop(..., delta=0.015)).
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec, {0.015});
  const fs::path out = ExpectImportValidatesAndConverts(
      "bop", scene, dir_.path(), spec.width, spec.height, [&](int k) {
        return ImportedIdsOfBlenderProcMasks(scene, spec, k);
      });
  const CollectionReader reader(out);
  const json infos = json::parse(ReadText(scene / "scene_gt_info.json"));
  int64_t overlapping = 0, wrong = 0;
  double visibility_error = 0;
  int k = 0;
  reader.ForEachFrame([&](const Frame& frame) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec, k);
    const std::vector<uint32_t> ids =
        exr::ReadFlatExr(reader.LayerPath(frame, "instanceid")).Get("id").uints;
    const std::vector<std::vector<uint32_t>> claims = MaskClaims(scene, spec, k);
    for (size_t p = 0; p < ids.size(); ++p) {
      if (claims[p].size() < 2) continue;
      ++overlapping;
      // The renderer's front object, which the depth shows.
      wrong += ids[p] != truth.flat.at("instanceid").Get("id").uints[p];
    }
    // visibility is BlenderProc's visib_fract, as written.
    for (const ObjectTruth& object : frame.objects)
      visibility_error = std::max(
          visibility_error,
          std::abs(object.visibility -
                   infos[std::to_string(k)][object.instance_id - 1]["visib_fract"].get<double>()));
    ++k;
  });
  EXPECT_GT(overlapping, 20);  // the masks of touching objects do overlap
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(visibility_error, 0);
  std::cout << "BlenderProc BOP: " << overlapping << " pixels in two masks, " << wrong
            << " given to another object than the renderer's front one; max |visibility - "
               "visib_fract| "
            << visibility_error << "\n";
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
