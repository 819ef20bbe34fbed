// lsds import ue-mrq: a Movie Render Queue folder synthesized from an analytic
// scene (mrq_fixture.h) imports into a collection whose truth equals the
// scene's known truth, validates clean and converts to COCO masks equal to the
// fixture's id layers.
#include <cmath>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "importers/cryptomatte.h"
#include "importers/import_collection.h"
#include "importers/unreal_frame.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "synth/synthetic_collection.h"
#include "tests/convert/reference_decoders.h"
#include "tests/import/mrq_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// DefaultSpec's nadir frames plus an oblique, rolled view that sees the sky:
// one sample per pixel, so the Cryptomatte rank 0 is the pixel-centre id.
synth::Spec FixtureSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.samples_per_axis = 1;
  const Rigid3d look = LookAt({-14, -9, 6}, {0, 0, 1});
  const Eigen::Quaterniond roll(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  spec.cam_from_world.push_back(Rigid3d(roll, Eigen::Vector3d::Zero()) * look);
  return spec;
}

std::vector<Frame> Frames(const fs::path& root) {
  std::vector<Frame> frames;
  CollectionReader(root).ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  return frames;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class UeMrqImportTest : public ::testing::Test {
 protected:
  void SetUp() override { spec_ = FixtureSpec(); }
  fs::path Import(const MrqFixtureOptions& options, const std::string& name) {
    const fs::path source = dir_ / (name + "-mrq");
    WriteMrqFixture(source, spec_, options);
    const fs::path out = dir_ / (name + "-collection");
    import::ImportCollection("ue-mrq", source, out, {}, false);
    return out;
  }
  TempDir dir_;
  synth::Spec spec_;
};

TEST(Cryptomatte, HashesAndFloatsFollowTheSpecification) {
  EXPECT_EQ(import::MurmurHash3_32(""), 0u);
  EXPECT_EQ(import::MurmurHash3_32("hello"), 0x248bfa47u);
  // Exponent 0 or 255 has its lowest exponent bit flipped: finite, normal.
  EXPECT_EQ(import::CryptomatteBitsFromHash(0x00000001u), 0x00800001u);
  EXPECT_EQ(import::CryptomatteBitsFromHash(0x7f800000u), 0x7f000000u);
  EXPECT_EQ(import::CryptomatteBitsFromHash(0x3f800000u), 0x3f800000u);
  EXPECT_TRUE(std::isnormal(import::CryptomatteFloatFromHash(0xffffffffu)));
}

TEST(UnrealFrame, CameraAndBoxRoundTripThroughRotators) {
  const Rigid3d pose = LookAt({3, -4, 12}, {1, 2, 0});
  Eigen::Vector3d location;
  import::UnrealRotator rotator;
  import::UnrealCameraOfCamFromEnu(pose, &location, &rotator);
  // Unreal: x north, y east, centimetres.
  EXPECT_NEAR(location.x(), -400, 1e-9);
  EXPECT_NEAR(location.y(), 300, 1e-9);
  EXPECT_NEAR(location.z(), 1200, 1e-9);
  const Rigid3d back = import::CamFromEnuOfUnrealCamera(location, rotator);
  EXPECT_LT((back.ToMatrix() - pose.ToMatrix()).cwiseAbs().maxCoeff(), 1e-12);
  // A camera with rotator 0 looks north, image right is east.
  const Rigid3d north = import::CamFromEnuOfUnrealCamera({0, 0, 0}, {});
  EXPECT_LT((north.rotation * Eigen::Vector3d(0, 1, 0) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((north.rotation * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
}

TEST_F(UeMrqImportTest, TruthEqualsTheAnalyticScene) {
  const fs::path out = Import({}, "multipart");
  const std::vector<Frame> frames = Frames(out);
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  const CollectionReader reader(out);
  EXPECT_EQ(reader.header().conventions.world.name, "ENU");
  EXPECT_EQ(reader.header().provenance.import["format"], "ue-mrq");
  EXPECT_EQ(reader.header().provenance.import["truth_origin"]["worldposition"], "derived");
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_NEAR(frame.time, truth.truth.time, 1e-12);
    EXPECT_EQ(frame.camera.intrinsics, truth.truth.camera.intrinsics);
    EXPECT_LT((frame.camera.cam_from_world_rotation - truth.truth.camera.cam_from_world_rotation)
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
    EXPECT_LT(
        (frame.camera.cam_from_world_translation - truth.truth.camera.cam_from_world_translation)
            .norm(),
        1e-9);
    ASSERT_EQ(frame.objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      const ObjectTruth& got = frame.objects[i];
      const ObjectTruth& want = truth.truth.objects[i];
      EXPECT_EQ(got.instance_id, want.instance_id);
      EXPECT_EQ(got.class_id, want.class_id);
      EXPECT_EQ(got.name, want.name);
      ASSERT_EQ(got.bbox.has_value(), want.bbox.has_value());
      if (got.bbox) {
        EXPECT_EQ(*got.bbox, *want.bbox);  // exact
      }
      EXPECT_EQ(got.visible_pixels, want.visible_pixels);
      EXPECT_NEAR(got.visibility, want.visibility, 1e-12);
      EXPECT_NEAR(got.in_frame, want.in_frame, 1e-9);
      EXPECT_LT((got.obb->center - want.obb->center).norm(), 1e-9);
      EXPECT_LT((got.obb->half_extents - want.obb->half_extents).norm(), 1e-9);
      EXPECT_LT((got.obb->world_from_box - want.obb->world_from_box).cwiseAbs().maxCoeff(), 1e-12);
    }
    // Layers: ids exact, depth and world position within float precision.
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, truth.flat.at("instanceid").Get("id").uints);
    EXPECT_EQ(read("classid").Get("id").uints, truth.flat.at("classid").Get("id").uints);
    const std::vector<float> depth = read("depth").Get("Z").floats;
    const std::vector<float>& want_depth = truth.flat.at("depth").Get("Z").floats;
    // Read through the collection's reader: X, Y, Z whatever the layer's layout.
    const exr::FlatImage position = reader.ReadFlatLayer(frame, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage& want_position = truth.flat.at("worldposition");
    int sky = 0;
    for (size_t p = 0; p < depth.size(); ++p) {
      if (std::isinf(want_depth[p])) {
        ++sky;
        EXPECT_TRUE(std::isinf(depth[p]));
        EXPECT_TRUE(std::isinf(position.Get("X").floats[p]));
        continue;
      }
      EXPECT_NEAR(depth[p], want_depth[p], 2e-7 * want_depth[p]);
      for (const char* c : {"X", "Y", "Z"})
        EXPECT_NEAR(
            position.Get(c).floats[p], want_position.Get(c).floats[p], 1e-6 * want_depth[p] + 2e-6)
            << c << " pixel " << p;
    }
    if (k == frames.size() - 1) {
      EXPECT_GT(sky, 0);  // the oblique view
    }
  }
}

TEST_F(UeMrqImportTest, SinglePartMultilayerAndHalfDepthImportAlike) {
  MrqFixtureOptions options;
  options.multipart = false;
  options.half_depth = true;
  const fs::path out = Import(options, "singlepart");
  const std::vector<Frame> frames = Frames(out);
  const CollectionReader reader(out);
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    ASSERT_EQ(frames[k].objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frames[k].objects.size(); ++i)
      EXPECT_EQ(frames[k].objects[i].bbox, truth.truth.objects[i].bbox);
    // Half: 11 significant bits, so depth within 2^-11 relative; centimetres
    // beyond the largest half (65504, rounding to inf from 65520) are lost:
    // a half depth pass ends at 655 m and reads as sky beyond.
    const std::vector<float> depth =
        exr::ReadFlatExr(reader.LayerPath(frames[k], "depth")).Get("Z").floats;
    const std::vector<float>& want = truth.flat.at("depth").Get("Z").floats;
    int saturated = 0;
    for (size_t p = 0; p < depth.size(); ++p) {
      if (std::isinf(want[p])) continue;
      if (want[p] * 100 >= 65520) {
        ++saturated;
        EXPECT_TRUE(std::isinf(depth[p]));
        continue;
      }
      EXPECT_NEAR(depth[p], want[p], want[p] / 2048.0);
    }
    if (k == frames.size() - 1) {
      EXPECT_GT(saturated, 0);
    }
  }
}

TEST_F(UeMrqImportTest, ValidatesCleanAndConvertsToCocoMasksOfTheIdLayers) {
  // As a user runs it: the sidecar elsewhere (--objects), the CLI end to end.
  const fs::path source = dir_ / "cli-mrq";
  WriteMrqFixture(source, spec_, {});
  const fs::path objects = dir_ / "objects.json";
  fs::rename(source / "lsds_objects.json", objects);
  const fs::path out = dir_ / "cli-collection";
  const CommandResult imported =
      RunCommandLine(LsdsBinary() + " import ue-mrq " + source.string() + " -o " + out.string() +
                     " --objects " + objects.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("imported 5 frames"), std::string::npos) << imported.output;
  const CommandResult again =
      RunCommandLine(LsdsBinary() + " import ue-mrq " + source.string() + " -o " + out.string() +
                     " --objects " + objects.string());
  EXPECT_EQ(again.exit_code, 2) << again.output;  // exists, no --force
  const CommandResult validate =
      RunCommandLine(LsdsBinary() + " validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  const fs::path coco = dir_ / "coco";
  const CommandResult convert = RunCommandLine(LsdsBinary() + " convert " + out.string() +
                                               " --to coco --images none -o " + coco.string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  fs::path annotations;
  for (const auto& entry : fs::recursive_directory_iterator(coco)) {
    if (entry.path().extension() == ".json" &&
        entry.path().filename().string().rfind("instances", 0) == 0)
      annotations = entry.path();
  }
  ASSERT_FALSE(annotations.empty());
  const json doc = json::parse(ReadText(annotations));
  std::map<int64_t, std::string> image_names;
  for (const json& image : doc["images"])
    image_names[image["id"].get<int64_t>()] = image["file_name"];
  ASSERT_GT(doc["annotations"].size(), 0u);
  const int w = spec_.width, h = spec_.height;
  for (const json& a : doc["annotations"]) {
    // The frame index is the image's file stem.
    const std::string stem = fs::path(image_names.at(a["image_id"].get<int64_t>())).stem().string();
    const int k = std::stoi(stem);
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, k);
    const uint32_t instance = a["lsds"]["instance_id"];
    const std::vector<uint32_t>& ids = truth.flat.at("instanceid").Get("id").uints;
    int64_t total = 0;
    const cv::Mat mask =
        CocoDecode(CocoCountsFromString(a["segmentation"]["counts"]), h, w, &total);
    ASSERT_EQ(total, int64_t{w} * h);
    int64_t differing = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        differing +=
            (mask.at<uint8_t>(j, i) != 0) != (ids[static_cast<size_t>(j) * w + i] == instance);
    EXPECT_EQ(differing, 0) << "instance " << instance << " frame " << k;
  }
}

TEST_F(UeMrqImportTest, RefusesExistingOutputAndOutputInsideTheSource) {
  const fs::path source = dir_ / "mrq";
  WriteMrqFixture(source, spec_, {});
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  EXPECT_THROW(import::ImportCollection("ue-mrq", source, out, {}, false), Error);
  EXPECT_THROW(import::ImportCollection("ue-mrq", source, source / "inside", {}, true), Error);
  const CommandResult unknown = RunCommandLine(LsdsBinary() + " import ue-mrqq " + source.string() +
                                               " -o " + (dir_ / "x").string());
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("did you mean 'ue-mrq'"), std::string::npos) << unknown.output;
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

TEST_F(UeMrqImportTest, ASourceThatIsNotWhatItClaimsGivesALocatedError) {
  const fs::path source = dir_ / "mrq";
  WriteMrqFixture(source, spec_, {});
  // An actor's hash missing from the manifest: named file and pixel.
  json objects = json::parse(ReadText(source / "lsds_objects.json"));
  objects["actors"][1]["class_id"] = 99;
  std::ofstream(source / "lsds_objects.json") << objects.dump();
  try {
    import::ImportCollection("ue-mrq", source, dir_ / "out", {}, false);
    FAIL() << "accepted an unknown class";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lsds_objects.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/actors/1/class_id"), std::string::npos) << e.what();
  }
  // A frame whose EXR is not an EXR: the file is named; nothing is written.
  objects["actors"][1]["class_id"] = 2;
  std::ofstream(source / "lsds_objects.json") << objects.dump();
  std::ofstream(source / "Shot.0002.exr") << "not an exr";
  const CommandResult result = RunCommandLine(LsdsBinary() + " import ue-mrq " + source.string() +
                                              " -o " + (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("Shot.0002.exr"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
}  // namespace lsds::testing
