// lsds import solo: a Unity Perception SOLO dataset synthesized from an
// analytic scene (solo_fixture.h) imports into a collection whose truth equals
// the scene's known truth after Unity's left-handed y-up world, its camera and
// its [x, y, z, w] quaternions are converted, validates clean and converts to
// COCO masks equal to the fixture's instance segmentation.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "importers/import_collection.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "tests/import/import_checks.h"
#include "tests/import/solo_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSplit = 3;  // frames [0, 3) in sequence.0, the rest sequence.1

// The fixture's ids: box b is Unity instance 100 + b; the ground is black.
std::vector<uint32_t> SoloIds(const synth::Spec& spec, const synth::RenderedFrame& truth) {
  std::vector<uint32_t> ids = truth.flat.at("instanceid").Get("id").uints;
  for (uint32_t& id : ids) {
    uint32_t mapped = 0;
    for (size_t b = 0; b < spec.boxes.size(); ++b)
      if (id == spec.boxes[b].instance_id) mapped = kSoloInstanceBase + static_cast<uint32_t>(b);
    id = mapped;
  }
  return ids;
}

class SoloImportTest : public ::testing::Test {
 protected:
  TempDir dir_;
  synth::Spec spec_ = ObliqueImportSpec();
};

TEST_F(SoloImportTest, TruthEqualsTheAnalyticScene) {
  const fs::path dataset = dir_ / "solo";
  WriteSoloFixture(dataset, spec_, kSplit);
  const fs::path out = dir_ / "collection";
  import::ImportCollection("solo", dataset, out, {}, false);
  const CollectionReader reader(out);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    const int step = k < kSplit ? static_cast<int>(k) : static_cast<int>(k) - kSplit;
    EXPECT_EQ(frame.sequence, k < kSplit ? "sequence.0" : "sequence.1");
    EXPECT_EQ(frame.shot, k < kSplit ? 0 : kSplit);
    EXPECT_NEAR(frame.time, step * spec_.frame_interval, 1e-12);
    // Unity: left-handed y-up world, +z-forward camera, [x, y, z, w].
    ExpectCameraNear(frame.camera, truth.truth.camera, 1e-12, 1e-12);
    ASSERT_EQ(frame.objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      const ObjectTruth& got = frame.objects[i];
      const ObjectTruth& want = truth.truth.objects[i];
      EXPECT_EQ(got.instance_id, kSoloInstanceBase + want.instance_id - 1);
      EXPECT_EQ(got.class_id, want.class_id);
      ExpectObjectNear(got, want, 1e-12);
    }
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, SoloIds(spec_, truth));
    // Unity's depth EXR is float32 metres: exact; 0 (nothing) is +inf.
    const std::vector<float> depth = read("depth").Get("Z").floats;
    const std::vector<float>& want = truth.flat.at("depth").Get("Z").floats;
    // Read through the collection's reader: X, Y, Z whatever the layer's layout.
    const exr::FlatImage position = reader.ReadFlatLayer(frame, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage& want_position = truth.flat.at("worldposition");
    for (size_t p = 0; p < depth.size(); ++p) {
      if (!std::isfinite(want[p])) {
        EXPECT_TRUE(std::isinf(depth[p]));
        continue;
      }
      EXPECT_EQ(depth[p], want[p]);
      for (const char* c : {"X", "Y", "Z"})
        EXPECT_NEAR(position.Get(c).floats[p], want_position.Get(c).floats[p], 2e-6 * want[p]);
    }
  }
}

TEST_F(SoloImportTest, ValidatesCleanAndConverts) {
  const fs::path dataset = dir_ / "solo";
  WriteSoloFixture(dataset, spec_, kSplit);
  ExpectImportValidatesAndConverts(
      "solo", dataset, dir_.path(), spec_.width, spec_.height, [&](int k) {
        return SoloIds(spec_, synth::RenderFrame(spec_, k));
      });
}

// Perception before 1.0 writes no `timestamp`: the RGB sensor's schedule in
// sensor_definitions.json (simulationDeltaTime, firstCaptureFrame, framesBetweenCaptures) gives
// each step's time, the same the 1.0 writer stamps.
TEST_F(SoloImportTest, FramesWithoutTimestampTakeTheSensorSchedule) {
  const fs::path dataset = dir_ / "solo";
  WriteSoloFixture(dataset, spec_, kSplit);
  for (const auto& entry : fs::recursive_directory_iterator(dataset)) {
    if (entry.path().filename().string().find("frame_data.json") == std::string::npos) continue;
    json data = json::parse(ReadText(entry.path()));
    data.erase("timestamp");
    std::ofstream(entry.path()) << data.dump();
  }
  // Every second simulated frame captured, from frame 3 on.
  json sensors = json::parse(ReadText(dataset / "sensor_definitions.json"));
  sensors["sensorDefinitions"][0]["framesBetweenCaptures"] = 1;
  sensors["sensorDefinitions"][0]["firstCaptureFrame"] = 3.0;
  std::ofstream(dataset / "sensor_definitions.json") << sensors.dump();
  const fs::path out = dir_ / "collection";
  import::ImportCollection("solo", dataset, out, {}, false);
  std::vector<double> times;
  CollectionReader(out).ForEachFrame([&](const Frame& f) { times.push_back(f.time); });
  ASSERT_EQ(times.size(), spec_.cam_from_world.size());
  for (size_t k = 0; k < times.size(); ++k) {
    const int step = k < kSplit ? static_cast<int>(k) : static_cast<int>(k) - kSplit;
    EXPECT_NEAR(times[k], spec_.frame_interval * (3 + 2 * step), 1e-12) << "frame " << k;
  }
}

TEST_F(SoloImportTest, ABadQuaternionIsALocatedError) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(2);
  const fs::path dataset = dir_ / "solo";
  WriteSoloFixture(dataset, spec, 1);
  const fs::path step = dataset / "sequence.1" / "step0.frame_data.json";
  json data = json::parse(ReadText(step));
  data["captures"][0]["annotations"][1]["values"][2]["rotation"] = {0, 0, 0, 2};
  std::ofstream(step) << data.dump();
  const CommandResult result = RunCommandLine(LsdsBinary() + " import solo " + dataset.string() +
                                              " -o " + (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("step0.frame_data.json#/captures/0/annotations/1/values/2/rotation"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
}  // namespace lsds::testing
