// lsds import kubric: a Kubric scene folder synthesized from an analytic scene
// (kubric_fixture.h) imports into a collection whose truth equals the scene's
// known truth, validates clean and converts to COCO masks equal to the
// fixture's segmentation and YOLO boxes equal to the truth.
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "importers/import_collection.h"
#include "importers/indexed_png.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/import/import_checks.h"
#include "tests/import/kubric_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

synth::Spec KubricSpec() {
  synth::Spec spec = ObliqueImportSpec();
  spec.depth_kind = DepthKind::kPerspective;  // Kubric's depth: ray distance
  return spec;
}

class KubricImportTest : public ::testing::Test {
 protected:
  TempDir dir_;
  synth::Spec spec_ = KubricSpec();
};

// Kubric's segmentation PNGs through libpng: a palette image reads back its
// indices; a colour PNG and a truncated one are errors naming the file (the
// second through libpng's longjmp), and reading goes on working afterwards.
TEST(IndexedPng, RoundTripAndErrorsNameTheFile) {
  TempDir dir;
  import::IndexImage image;
  image.width = 5;
  image.height = 3;
  for (int i = 0; i < 15; ++i) image.index.push_back(static_cast<uint8_t>(i % 4));
  const std::vector<uint8_t> palette = {0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255};
  import::WriteIndexedPng(dir / "seg.png", image, palette);
  const import::IndexImage read = import::ReadIndexedPng(dir / "seg.png");
  EXPECT_EQ(read.width, 5);
  EXPECT_EQ(read.height, 3);
  EXPECT_EQ(read.index, image.index);

  cv::imwrite((dir / "colour.png").string(), cv::Mat(3, 5, CV_8UC3, cv::Scalar(1, 2, 3)));
  // The message of the lsds::Error that reading `path` throws.
  auto error_of = [](const fs::path& path) -> std::string {
    try {
      import::ReadIndexedPng(path);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  std::string error = error_of(dir / "colour.png");
  EXPECT_NE(error.find("colour.png"), std::string::npos) << error;
  EXPECT_NE(error.find("indexed"), std::string::npos) << error;

  const std::string bytes = ReadFile(dir / "seg.png");
  WriteFileAtomic(dir / "truncated.png", bytes.substr(0, bytes.size() / 2));
  error = error_of(dir / "truncated.png");
  EXPECT_NE(error.find("truncated.png"), std::string::npos) << error;
  EXPECT_NE(error.find("not a readable PNG"), std::string::npos) << error;

  EXPECT_EQ(import::ReadIndexedPng(dir / "seg.png").index, image.index);
}

TEST_F(KubricImportTest, TruthEqualsTheAnalyticScene) {
  const fs::path scene = dir_ / "kubric" / "0";
  WriteKubricFixture(scene, spec_);
  const fs::path out = dir_ / "collection";
  import::ImportCollection("kubric", scene, out, {}, false);
  const CollectionReader reader(out);
  EXPECT_EQ(reader.header().layers.size(), 5u);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_NEAR(frame.time, k * spec_.frame_interval, 1e-12);
    // Blender camera (-Z forward, +Y up), WXYZ quaternion -> OpenCV camera;
    // the OBB from the 8 corners.
    ExpectCameraNear(frame.camera, truth.truth.camera, 1e-12, 1e-12);
    ASSERT_EQ(frame.objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      const ObjectTruth& got = frame.objects[i];
      const ObjectTruth& want = truth.truth.objects[i];
      EXPECT_EQ(got.instance_id, want.instance_id);
      ExpectObjectNear(got, want, 1e-12);
    }
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, TargetIds(truth));
    // Ray distance stored as perspective depth: float32 exactly; the
    // background (1e10) is +inf.
    const std::vector<float> depth = read("depth").Get("Z").floats;
    const std::vector<float>& want = truth.flat.at("depth").Get("Z").floats;
    // Read through the collection's reader: X, Y, Z whatever the layer's layout.
    const exr::FlatImage position = reader.ReadFlatLayer(frame, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage& want_position = truth.flat.at("worldposition");
    int sky = 0;
    for (size_t p = 0; p < depth.size(); ++p) {
      if (!std::isfinite(want[p])) {
        EXPECT_TRUE(std::isinf(depth[p]));
        ++sky;
        continue;
      }
      EXPECT_EQ(depth[p], want[p]);
      for (const char* c : {"X", "Y", "Z"})
        EXPECT_NEAR(position.Get(c).floats[p], want_position.Get(c).floats[p], 2e-6 * want[p]);
    }
    if (k == frames.size() - 1) {
      EXPECT_GT(sky, 0);
    }
  }
  const json header = json::parse(ReadText(out / "collection.json"));
  const json& origin = header["provenance"]["import"]["truth_origin"];
  EXPECT_EQ(origin["obb"], "imported");
  EXPECT_EQ(origin["depth"], "imported");
  EXPECT_EQ(origin["normal"], "absent");
}

TEST_F(KubricImportTest, ValidatesCleanAndConverts) {
  const fs::path scene = dir_ / "kubric" / "0";
  WriteKubricFixture(scene, spec_);
  ExpectImportValidatesAndConverts(
      "kubric", scene, dir_.path(), spec_.width, spec_.height, [&](int k) {
        return TargetIds(synth::RenderFrame(spec_, k));
      });
}

// lsds import --compact: worldposition stored in the residual layout (lsds info says so), every
// layer of every frame decoded bit for bit as the plain import's (the sky's +inf included), and
// both collections validate clean.
TEST_F(KubricImportTest, CompactStoresTheSameLayersInTheResidualLayout) {
  const fs::path scene = dir_ / "kubric" / "0";
  WriteKubricFixture(scene, spec_);
  const fs::path plain = dir_ / "plain", compact = dir_ / "compact";
  for (const auto& [out, flags] : {std::pair{plain, ""}, std::pair{compact, " --compact"}}) {
    CommandResult r = RunCommandLine(LsdsBinary() + " import kubric " + scene.string() + " -o " +
                                     out.string() + flags);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = RunCommandLine(LsdsBinary() + " validate --fail-on warning " + out.string());
    EXPECT_EQ(r.exit_code, 0) << flags << ": " << r.output;
    r = RunCommandLine(LsdsBinary() + " info --json " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const json info = json::parse(r.output);
    std::string layout;
    for (const json& layer : info["layers"])
      if (layer["semantic"] == "worldposition") layout = layer.value("layout", "");
    EXPECT_EQ(layout, out == compact ? "residual" : "float") << r.output;
  }
  const CollectionReader plain_reader(plain), compact_reader(compact);
  std::vector<Frame> plain_frames, compact_frames;
  plain_reader.ForEachFrame([&](const Frame& f) { plain_frames.push_back(f); });
  compact_reader.ForEachFrame([&](const Frame& f) { compact_frames.push_back(f); });
  ASSERT_EQ(plain_frames.size(), spec_.cam_from_world.size());
  ASSERT_EQ(compact_frames.size(), plain_frames.size());
  int64_t non_finite = 0;
  for (const LayerInfo& layer : plain_reader.header().layers) {
    std::vector<std::string> channels;
    for (const LayerChannel& c : layer.channels) channels.push_back(c.name);
    for (size_t k = 0; k < plain_frames.size(); ++k) {
      SCOPED_TRACE(layer.name + " frame " + std::to_string(k));
      const exr::FlatImage want = plain_reader.ReadFlatLayer(plain_frames[k], layer.name, channels);
      const exr::FlatImage got =
          compact_reader.ReadFlatLayer(compact_frames[k], layer.name, channels);
      for (const std::string& name : channels) {
        const exr::FlatChannel& a = want.Get(name);
        const exr::FlatChannel& b = got.Get(name);
        ASSERT_EQ(a.type, b.type) << name;
        ASSERT_EQ(a.floats.size(), b.floats.size()) << name;
        // A uint channel holds no floats: memcmp is not called with null pointers.
        if (!a.floats.empty()) {
          EXPECT_EQ(std::memcmp(a.floats.data(), b.floats.data(), a.floats.size() * sizeof(float)),
                    0)
              << name;
        }
        EXPECT_EQ(a.uints, b.uints) << name;
        if (layer.semantic == "worldposition")
          for (float v : b.floats) non_finite += std::isfinite(v) ? 0 : 1;
      }
    }
  }
  EXPECT_GT(non_finite, 0);  // the sky's +inf went through the residual layout
}

TEST_F(KubricImportTest, ASourceThatIsNotWhatItClaimsGivesALocatedError) {
  const fs::path scene = dir_ / "kubric" / "0";
  WriteKubricFixture(scene, spec_);
  json metadata = json::parse(ReadText(scene / "metadata.json"));
  metadata["instances"][1]["bboxes_3d"][2][5] = {1, 2};
  std::ofstream(scene / "metadata.json") << metadata.dump();
  const CommandResult result = RunCommandLine(LsdsBinary() + " import kubric " + scene.string() +
                                              " -o " + (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("metadata.json#/instances/1/bboxes_3d/2"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(KubricImportTest, ASegmentationIndexWithoutInstanceNamesThePixel) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(1);
  const fs::path scene = dir_ / "kubric" / "0";
  WriteKubricFixture(scene, spec);
  json metadata = json::parse(ReadText(scene / "metadata.json"));
  metadata["instances"].erase(2);  // the crate's pixels now name no instance
  metadata["metadata"]["num_instances"] = 2;
  std::ofstream(scene / "metadata.json") << metadata.dump();
  const CommandResult result = RunCommandLine(LsdsBinary() + " import kubric " + scene.string() +
                                              " -o " + (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("segmentation_00000.png"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("segmentation index 3"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace lsds::testing

namespace lsds::testing {
namespace {

// structure.truth-origin: what the source could not provide is information in
// `lsds validate`, located at the truth_origin field; a rendered collection
// has none.
TEST_F(KubricImportTest, ValidateReportsTheAbsentTruthAsInformation) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(1);
  const fs::path scene = dir_ / "kubric" / "0";
  WriteKubricFixture(scene, spec);
  const fs::path out = dir_ / "collection";
  import::ImportCollection("kubric", scene, out, {}, false);
  const fs::path report_file = dir_ / "report.json";
  const CommandResult report =
      RunCommandLine(LsdsBinary() + " validate --format json --fail-on info -o " +
                     report_file.string() + " " + out.string());
  EXPECT_EQ(report.exit_code, 1) << report.output;
  const json doc = json::parse(ReadText(report_file));
  std::set<std::string> pointers;
  for (const json& check : doc["checks"]) {
    if (check["id"] != "structure.truth-origin") continue;
    EXPECT_EQ(check["severity"], "info");
    for (const json& finding : check["findings"])
      pointers.insert(finding["location"]["json_pointer"].get<std::string>());
  }
  const std::set<std::string> want = {"/provenance/import/truth_origin/bundle",
                                      "/provenance/import/truth_origin/motion",
                                      "/provenance/import/truth_origin/normal",
                                      "/provenance/import/truth_origin/shadow",
                                      "/provenance/import/truth_origin/visibility"};
  for (const std::string& p : want) EXPECT_EQ(pointers.count(p), 1u) << p;
  // Only absent fields and the estimated visibility: not depth (imported) nor
  // bbox (derived exactly from the id layer).
  EXPECT_EQ(pointers.count("/provenance/import/truth_origin/depth"), 0u);
  EXPECT_EQ(pointers.count("/provenance/import/truth_origin/bbox"), 0u);
  const CommandResult warning =
      RunCommandLine(LsdsBinary() + " validate --fail-on warning " + out.string());
  EXPECT_EQ(warning.exit_code, 0) << warning.output;

  const fs::path rendered = dir_ / "rendered";
  synth::WriteCollection(rendered, spec);
  const CommandResult clean =
      RunCommandLine(LsdsBinary() +
                     " validate --format json --checks structure.truth-origin "
                     "--fail-on info " +
                     rendered.string());
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
}

}  // namespace
}  // namespace lsds::testing
