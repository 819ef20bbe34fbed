// lsds import airsim: a recording folder synthesized from an analytic scene
// (airsim_fixture.h) imports into a collection whose truth equals the scene's
// known truth, validates clean and converts to COCO masks equal to the
// fixture's segmentation.
#include <cmath>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "importers/import_collection.h"
#include "importers/pfm.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "tests/convert/reference_decoders.h"
#include "tests/import/airsim_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

synth::Spec FixtureSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.samples_per_axis = 1;
  const Rigid3d look = LookAt({-14, -9, 6}, {0, 0, 1});
  const Eigen::Quaterniond roll(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  spec.cam_from_world.push_back(Rigid3d(roll, Eigen::Vector3d::Zero()) * look);
  return spec;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Pfm, RowOrderIsTheCallersToState) {
  TempDir dir;
  import::PfmImage image{3, 2, 1, { 1, 2, 3, 4, 5, 6 }};  // top row 1 2 3
  import::WritePfm(dir / "top.pfm", image, import::PfmRows::kTopFirst);
  // The file holds the top row first: read as the specification says (bottom
  // first), the image comes out upside down.
  EXPECT_EQ(import::ReadPfm(dir / "top.pfm", import::PfmRows::kTopFirst).values, image.values);
  EXPECT_EQ(import::ReadPfm(dir / "top.pfm", import::PfmRows::kBottomFirst).values,
            (std::vector<float>{4, 5, 6, 1, 2, 3}));
  const std::string text = ReadText(dir / "top.pfm");
  EXPECT_EQ(text.substr(0, 10), "Pf\n3 2\n-1\n");
  std::ofstream(dir / "short.pfm") << "Pf\n3 2\n-1\n1234";
  EXPECT_THROW(import::ReadPfm(dir / "short.pfm", import::PfmRows::kTopFirst), Error);
}

TEST(AirSimPose, VehiclePoseAndMountRoundTrip) {
  const Rigid3d pose = LookAt({3, -4, 12}, {1, 2, 0});
  Eigen::Vector3d position;
  Eigen::Quaterniond q;
  import::AirSimVehicleOfCamFromEnu(pose, AirSimFixtureMount(), &position, &q);
  const Rigid3d back = import::CamFromEnuOfAirSim(position, q, AirSimFixtureMount());
  EXPECT_LT((back.ToMatrix() - pose.ToMatrix()).cwiseAbs().maxCoeff(), 1e-12);
  // A level vehicle with a forward camera looks north (NED x), image right
  // east, at altitude -z.
  const Rigid3d level = import::CamFromEnuOfAirSim({0, 0, -10}, Eigen::Quaterniond::Identity(), {});
  EXPECT_LT((level.rotation * Eigen::Vector3d(0, 1, 0) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((level.rotation * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LT((CameraCenterInWorld(level) - Eigen::Vector3d(0, 0, 10)).norm(), 1e-12);
}

class AirSimImportTest : public ::testing::Test {
 protected:
  TempDir dir_;
  synth::Spec spec_ = FixtureSpec();
};

TEST_F(AirSimImportTest, TruthEqualsTheAnalyticScene) {
  const fs::path source = dir_ / "rec";
  WriteAirSimFixture(source, spec_);
  const fs::path out = dir_ / "collection";
  import::ImportCollection("airsim", source, out, {}, false);
  const CollectionReader reader(out);
  EXPECT_EQ(reader.header().provenance.import["format"], "airsim");
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_NEAR(frame.time, truth.truth.time, 1e-9);
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
      EXPECT_EQ(got.name, want.name);
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
    EXPECT_EQ(read("instanceid").Get("id").uints, truth.flat.at("instanceid").Get("id").uints);
    EXPECT_EQ(read("classid").Get("id").uints, truth.flat.at("classid").Get("id").uints);
    // Depth in metres, float to float: exact; the PFM's top row is row 0.
    EXPECT_EQ(read("depth").Get("Z").floats, truth.flat.at("depth").Get("Z").floats);
    // Read through the collection's reader: X, Y, Z whatever the layer's layout.
    const exr::FlatImage position = reader.ReadFlatLayer(frame, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage& want = truth.flat.at("worldposition");
    const std::vector<float>& depth = truth.flat.at("depth").Get("Z").floats;
    for (size_t p = 0; p < depth.size(); ++p) {
      if (std::isinf(depth[p])) continue;
      for (const char* c : {"X", "Y", "Z"})
        EXPECT_NEAR(position.Get(c).floats[p], want.Get(c).floats[p], 1e-6 * depth[p] + 2e-6);
    }
  }
}

TEST_F(AirSimImportTest, ValidatesCleanAndConvertsToCocoMasksOfTheSegmentation) {
  const fs::path source = dir_ / "rec";
  WriteAirSimFixture(source, spec_);
  const fs::path settings = dir_ / "settings.json";
  fs::rename(source / "settings.json", settings);  // as in ~/Documents/AirSim
  const fs::path out = dir_ / "collection";
  const CommandResult imported =
      RunCommandLine(LsdsBinary() + " import airsim " + source.string() + " -o " + out.string() +
                     " --settings " + settings.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
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
    const int k = std::stoi(fs::path(image_names.at(a["image_id"].get<int64_t>())).stem().string());
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, k);
    const uint32_t instance = a["lsds"]["instance_id"];
    const std::vector<uint32_t>& ids = truth.flat.at("instanceid").Get("id").uints;
    int64_t total = 0;
    const cv::Mat mask =
        CocoDecode(CocoCountsFromString(a["segmentation"]["counts"]), h, w, &total);
    int64_t differing = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        differing +=
            (mask.at<uint8_t>(j, i) != 0) != (ids[static_cast<size_t>(j) * w + i] == instance);
    EXPECT_EQ(differing, 0) << "instance " << instance << " frame " << k;
  }
}

// A DepthPlanar capture of its own size (CaptureSettings ImageType 1 at twice the Scene's) is
// another camera than the Scene's: AirSim renders it through its own SceneCapture component
// (PIPCamera.cpp, one capture per image type). The import leaves it out and says so; the rest
// imports, validates and keeps its truth.
TEST_F(AirSimImportTest, ADepthCaptureOfItsOwnSizeIsLeftOutAndSaid) {
  const fs::path source = dir_ / "rec";
  WriteAirSimFixture(source, spec_);
  json settings = json::parse(ReadText(source / "settings.json"));
  json& captures = settings["Vehicles"]["Drone1"]["Cameras"][kAirSimCamera]["CaptureSettings"];
  for (json& capture : captures)
    if (capture["ImageType"] == 1) {
      capture["Width"] = 2 * spec_.width;
      capture["Height"] = 2 * spec_.height;
    }
  std::ofstream(source / "settings.json") << settings.dump(2);
  const fs::path out = dir_ / "collection";
  const CommandResult imported =
      RunLsds("import airsim " + source.string() + " -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("the DepthPlanar (type 1) images are not read: settings.json "
                                 "gives them a capture of their own (" +
                                 std::to_string(2 * spec_.width) + "x" +
                                 std::to_string(2 * spec_.height)),
            std::string::npos)
      << imported.output;
  const CommandResult validate = RunLsds("validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  const CollectionReader reader(out);
  std::vector<std::string> semantics;
  for (const LayerInfo& layer : reader.header().layers) semantics.push_back(layer.semantic);
  EXPECT_EQ(semantics, (std::vector<std::string>{"rgb", "classid", "instanceid"}));
  // The Segmentation keeps the Scene's capture: its objects are there, as without the change.
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_FALSE(frames.empty());
  EXPECT_FALSE(frames[0].objects.empty());
}

TEST_F(AirSimImportTest, ASourceThatIsNotWhatItClaimsGivesALocatedError) {
  const fs::path source = dir_ / "rec";
  WriteAirSimFixture(source, spec_);
  // Two objects on one segmentation colour (AirSim's 256-colour palette).
  json objects = json::parse(ReadText(source / "lsds_objects.json"));
  objects["objects"][2]["color"] = objects["objects"][1]["color"];
  std::ofstream(source / "lsds_objects.json") << objects.dump();
  try {
    import::ImportCollection("airsim", source, dir_ / "out", {}, false);
    FAIL() << "accepted a shared colour";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/objects/2/color"), std::string::npos) << e.what();
  }
  WriteAirSimFixture(dir_ / "rec2", spec_);
  // A row whose position is not a number: file and line.
  std::string rec = ReadText(dir_ / "rec2" / "airsim_rec.txt");
  const size_t second_row = rec.find('\n', rec.find('\n') + 1) + 1;
  const size_t x = rec.find('\t', rec.find('\t', second_row) + 1) + 1;
  rec.replace(x, rec.find('\t', x) - x, "north");
  std::ofstream(dir_ / "rec2" / "airsim_rec.txt") << rec;
  const CommandResult result =
      RunCommandLine(LsdsBinary() + " import airsim " + (dir_ / "rec2").string() + " -o " +
                     (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("airsim_rec.txt:3"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("POS_X"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
}  // namespace lsds::testing
