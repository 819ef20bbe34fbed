// lsds import solo on real Perception 0.10 output (tests/import/fixtures/solo_real, from
// Unity-Technologies/pysolotools' test data; README there): frames with no `timestamp`,
// a label (Character) with a 2D box but no 3D box, labels defined but never used. The
// collection's truth is compared with the source's own annotations: the writer's
// BoundingBox2D boxes and RenderedObjectInfo pixel counts, the projection matrix, the
// capture's pose and the 3D boxes in the camera's frame.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "tests/build_paths.h"
#include "tests/import/import_checks.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path Fixture() { return fs::path(SourceDir()) / "tests/import/fixtures/solo_real"; }

json FrameData() {
  return json::parse(ReadText(Fixture() / "sequence.0" / "step0.frame_data.json"));
}

// The RGB capture's annotation of `type` (the suffix of its @type).
const json& Annotation(const json& frame_data, const std::string& type) {
  for (const json& a : frame_data["captures"][0]["annotations"])
    if (a["@type"].get<std::string>() == "type.unity.com/unity.solo." + type) return a;
  throw std::runtime_error("no " + type);
}

// The writer's 2D boxes (origin, dimension: pixel-edge, top-left origin) by instance.
std::map<uint32_t, Box2d> SourceBoxes2d(const json& frame_data) {
  std::map<uint32_t, Box2d> boxes;
  for (const json& v : Annotation(frame_data, "BoundingBox2DAnnotation")["values"]) {
    const double x = v["origin"][0], y = v["origin"][1];
    boxes[v["instanceId"]] = {
        x, y, x + v["dimension"][0].get<double>(), y + v["dimension"][1].get<double>()};
  }
  return boxes;
}

// RenderedObjectInfo's visible pixel counts by instance.
std::map<uint32_t, int64_t> SourceVisiblePixels(const json& frame_data) {
  std::map<uint32_t, int64_t> pixels;
  for (const json& m : frame_data["metrics"])
    if (m["id"] == "RenderedObjectInfo")
      for (const json& v : m["values"]) pixels[v["instanceId"]] = v["visiblePixels"];
  return pixels;
}

class SoloRealTest : public ::testing::Test {
 protected:
  // Imports the fixture once per test with `flags`; the command's output in import_output_.
  fs::path Import(const std::string& flags = "") {
    const fs::path out = dir_ / "collection";
    const CommandResult result =
        RunCommandLine(LsdsBinary() + " import solo \"" + Fixture().string() + "\" -o " +
                       out.string() + " " + flags);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    import_output_ = result.output;
    return out;
  }
  TempDir dir_;
  std::string import_output_;
};

TEST_F(SoloRealTest, TruthEqualsTheWritersAnnotations) {
  const json data = FrameData();
  const fs::path out = Import();
  const CollectionReader reader(out);
  // Only the labels the frame uses (Crate on the boxes, Character in the instance mask).
  ASSERT_EQ(reader.header().classes.size(), 2u);
  EXPECT_EQ(reader.header().classes[0].id, 1u);
  EXPECT_EQ(reader.header().classes[0].name, "Crate");
  EXPECT_EQ(reader.header().classes[1].id, 5u);
  EXPECT_EQ(reader.header().classes[1].name, "Character");
  // The 2D-only Character box is an object without a 3D box, and the import says so.
  EXPECT_NE(import_output_.find("1 BoundingBox2D box(es) of 'Character' have no BoundingBox3D box: "
                                "objects without a 3D box"),
            std::string::npos)
      << import_output_;

  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), 1u);
  const Frame& frame = frames[0];
  // No timestamp before 1.0: sensor_definitions.json's schedule puts step 0 at
  // firstCaptureFrame (0) * simulationDeltaTime.
  EXPECT_EQ(frame.time, 0.0);
  EXPECT_EQ(frame.sequence, "sequence.0");

  // Intrinsics: the OpenGL projection's 3x3 (column-major) on the 1024 x 768 capture.
  const json& capture = data["captures"][0];
  const PinholeCamera& camera = frame.camera.intrinsics;
  EXPECT_EQ(camera.width, 1024);
  EXPECT_EQ(camera.height, 768);
  EXPECT_NEAR(camera.fx, 512 * capture["matrix"][0].get<double>(), 1e-9);
  EXPECT_NEAR(camera.fy, 384 * capture["matrix"][4].get<double>(), 1e-9);
  EXPECT_NEAR(camera.cx, 512.0, 1e-9);
  EXPECT_NEAR(camera.cy, 384.0, 1e-9);
  // Pose: the camera centre is the capture's position, Unity (x, y up, z) -> ENU (x, z, y).
  const Eigen::Matrix3d& cam_from_world_rotation = frame.camera.cam_from_world_rotation;
  const Eigen::Vector3d& cam_from_world_translation = frame.camera.cam_from_world_translation;
  const Eigen::Vector3d centre =
      -(cam_from_world_rotation.transpose() * cam_from_world_translation);
  const json& position = capture["position"];
  EXPECT_NEAR(centre.x(), position[0].get<double>(), 1e-9);
  EXPECT_NEAR(centre.y(), position[2].get<double>(), 1e-9);
  EXPECT_NEAR(centre.z(), position[1].get<double>(), 1e-9);

  // Objects: the two Crates (3D boxes) and the Character (a 2D box only). Their tight boxes are
  // the writer's 2D boxes and their pixel counts RenderedObjectInfo's, exactly (both come from the
  // same instance mask).
  const std::map<uint32_t, Box2d> boxes_2d = SourceBoxes2d(data);
  const std::map<uint32_t, int64_t> pixels = SourceVisiblePixels(data);
  std::map<uint32_t, json> boxes_3d;
  for (const json& v : Annotation(data, "BoundingBox3DAnnotation")["values"])
    boxes_3d[v["instanceId"]] = v;
  ASSERT_EQ(frame.objects.size(), 3u);
  double max_box_error = 0, max_centre_px_error = 0;
  int crates = 0;
  for (const ObjectTruth& o : frame.objects) {
    SCOPED_TRACE("instance " + std::to_string(o.instance_id));
    ASSERT_TRUE(o.bbox.has_value());
    const Box2d& want = boxes_2d.at(o.instance_id);
    for (double d :
         {o.bbox->x0 - want.x0, o.bbox->y0 - want.y0, o.bbox->x1 - want.x1, o.bbox->y1 - want.y1})
      max_box_error = std::max(max_box_error, std::abs(d));
    EXPECT_EQ(o.visible_pixels, pixels.at(o.instance_id));
    if (!boxes_3d.count(o.instance_id)) {
      // The Character: no 3D box, so no projected box; nothing in this Perception 0.10 frame
      // states its occlusion (no OcclusionMetric), so visibility and in_frame are not measured.
      EXPECT_EQ(o.instance_id, 1u);
      EXPECT_EQ(o.class_id, 5u);
      EXPECT_EQ(o.name, "Character#1");
      EXPECT_FALSE(o.obb.has_value());
      EXPECT_FALSE(o.bbox_projected.has_value());
      EXPECT_FALSE(o.bbox_oriented_projected.has_value());
      EXPECT_TRUE(o.bbox_oriented.has_value());
      EXPECT_EQ(o.visibility, 1.0);
      EXPECT_EQ(o.in_frame, 1.0);
      continue;
    }
    ++crates;
    EXPECT_EQ(o.class_id, 1u);
    ASSERT_TRUE(o.obb.has_value());
    // The OBB: size as written; its centre, seen by the imported camera, lands where the
    // writer's camera-frame translation projects (Unity camera: x right, y up, z forward).
    const json& box = boxes_3d.at(o.instance_id);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(2 * o.obb->half_extents[a], box["size"][a].get<double>(), 1e-9);
    const Eigen::Vector3d in_cam =
        cam_from_world_rotation * o.obb->center + cam_from_world_translation;
    const double tx = box["translation"][0], ty = box["translation"][1], tz = box["translation"][2];
    const double u = camera.cx + camera.fx * tx / tz, v = camera.cy - camera.fy * ty / tz;
    max_centre_px_error = std::max({max_centre_px_error,
                                    std::abs(camera.cx + camera.fx * in_cam.x() / in_cam.z() - u),
                                    std::abs(camera.cy + camera.fy * in_cam.y() / in_cam.z() - v)});
    EXPECT_NEAR(in_cam.z(), tz, 1e-6);
  }
  EXPECT_EQ(crates, 2);
  EXPECT_EQ(max_box_error, 0.0);
  EXPECT_LT(max_centre_px_error, 1e-6);

  // The Character (instance 1, label 5) is in the id layers: its pixels are RenderedObjectInfo's
  // count and their extent the writer's 2D box.
  const exr::FlatImage ids = exr::ReadFlatExr(reader.LayerPath(frame, "instanceid"));
  const exr::FlatImage classes = exr::ReadFlatExr(reader.LayerPath(frame, "classid"));
  int64_t count = 0;
  Box2d extent{1e9, 1e9, -1, -1};
  for (int j = 0; j < ids.height(); ++j)
    for (int i = 0; i < ids.width(); ++i) {
      if (ids.Get("id").uints[ids.Index(i, j)] != 1) continue;
      ++count;
      EXPECT_EQ(classes.Get("id").uints[classes.Index(i, j)], 5u);
      extent = {std::min(extent.x0, double(i)),
                std::min(extent.y0, double(j)),
                std::max(extent.x1, i + 1.0),
                std::max(extent.y1, j + 1.0)};
    }
  EXPECT_EQ(count, pixels.at(1));
  EXPECT_EQ(extent, boxes_2d.at(1));
}

TEST_F(SoloRealTest, ValidatesCleanAndConvertsToCoco) {
  const fs::path out = Import();
  const fs::path annotations = ExpectValidatesAndConvertsToCoco(out, dir_ / "coco");
  ASSERT_FALSE(annotations.empty());
  const json doc = json::parse(ReadText(annotations));
  // Every 2D box the writer wrote (two Crates and the Character, which has no 3D box) with its
  // box as [x, y, w, h] and its category.
  const json data = FrameData();
  const std::map<uint32_t, Box2d> boxes_2d = SourceBoxes2d(data);
  std::map<uint32_t, std::string> label_of;
  for (const json& v : Annotation(data, "BoundingBox2DAnnotation")["values"])
    label_of[v["instanceId"]] = v["labelName"];
  std::map<int64_t, std::string> category_name;
  for (const json& c : doc["categories"]) category_name[c["id"]] = c["name"];
  ASSERT_EQ(doc["annotations"].size(), boxes_2d.size());
  std::set<uint32_t> seen;
  for (const json& a : doc["annotations"]) {
    const uint32_t instance = a["lsds"]["instance_id"].get<uint32_t>();
    seen.insert(instance);
    const Box2d& want = boxes_2d.at(instance);
    EXPECT_EQ(a["bbox"], json({want.x0, want.y0, want.width(), want.height()}));
    EXPECT_EQ(category_name.at(a["category_id"]), label_of.at(instance));
    // The lsds extension carries a 3D box only where the source has one.
    EXPECT_EQ(a["lsds"].contains("obb"), instance != 1u);
  }
  EXPECT_EQ(seen.size(), boxes_2d.size());
  // pycocotools' loader (lsds check-export's port of its rules) keeps every box.
  const fs::path coco = dir_ / "coco-png";
  const CommandResult convert = RunCommandLine(LsdsBinary() + " convert " + out.string() +
                                               " --to coco --images png -o " + coco.string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  const CommandResult check = RunCommandLine(LsdsBinary() + " check-export coco " + coco.string());
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_NE(check.output.find("PASS: 0 finding(s)"), std::string::npos) << check.output;
}

// Perception 1.0's OcclusionLabeler adds a metric per frame (OcclusionMetricDefinition.cs: @type
// type.unity.com/unity.solo.OcclusionMetric; OcclusionMetricEntry.ToMessage: instanceId,
// percentVisible, percentInFrame, visibilityInFrame). Added to the real frame as the writer
// writes it, its visibilityInFrame and percentInFrame become the objects' visibility and in_frame,
// the Character's (no 3D box) too.
TEST_F(SoloRealTest, TheOcclusionMetricGivesVisibilityAndInFrame) {
  const fs::path source = dir_ / "solo";
  fs::copy(Fixture(), source, fs::copy_options::recursive);
  const fs::path step = source / "sequence.0" / "step0.frame_data.json";
  json data = FrameData();
  data["metrics"].push_back({{"@type", "type.unity.com/unity.solo.OcclusionMetric"},
                             {"id", "Occlusion"},
                             {"sensorId", "camera"},
                             {"annotationId", ""},
                             {"description", "Visibility metrics for labeled objects"},
                             {"values",
                              {{{"instanceId", 1},
                                {"percentVisible", 0.5},
                                {"percentInFrame", 0.625},
                                {"visibilityInFrame", 0.8}},
                               {{"instanceId", 3},
                                {"percentVisible", 0.375},
                                {"percentInFrame", 0.75},
                                {"visibilityInFrame", 0.5}}}}});
  std::ofstream(step) << data.dump(2);
  const fs::path out = dir_ / "collection";
  const CommandResult result =
      RunCommandLine(LsdsBinary() + " import solo " + source.string() + " -o " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::map<uint32_t, ObjectTruth> objects;
  CollectionReader(out).ForEachFrame([&](const Frame& f) {
    for (const ObjectTruth& o : f.objects) objects[o.instance_id] = o;
  });
  ASSERT_EQ(objects.size(), 3u);
  EXPECT_EQ(objects.at(1).visibility, 0.8);
  EXPECT_EQ(objects.at(1).in_frame, 0.625);
  EXPECT_EQ(objects.at(3).visibility, 0.5);
  EXPECT_EQ(objects.at(3).in_frame, 0.75);
  // Instance 2 is not listed: its visibility is derived from the mask and its OBB.
  EXPECT_GT(objects.at(2).visibility, 0.0);
  EXPECT_LE(objects.at(2).visibility, 1.0);
  const CommandResult validate =
      RunCommandLine(LsdsBinary() + " validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;

  // A share outside [0, 1] is refused where it is.
  data["metrics"][4]["values"][0]["visibilityInFrame"] = 1.5;
  std::ofstream(step) << data.dump(2);
  const CommandResult bad = RunCommandLine(LsdsBinary() + " import solo " + source.string() +
                                           " -o " + (dir_ / "bad").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("step0.frame_data.json#/metrics/4/values/0"), std::string::npos)
      << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(SoloRealTest, AllLabelsKeepsTheLabelConfiguration) {
  const fs::path out = Import("--all-labels");
  const CollectionReader reader(out);
  std::vector<std::string> names;
  for (const ClassInfo& c : reader.header().classes) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"Crate", "Cube", "Box", "Terrain", "Character"}));
}

}  // namespace
}  // namespace lsds::testing
