// Camera rigs (docs/languages.md "Camera rigs", docs/format.md "Camera rigs"):
// several cameras with fixed poses on one platform. The plan (one frame per
// camera per time step, shared time and world, each camera's intrinsics), a
// stereo pair's disparity against its known baseline on a known point, a
// nadir + oblique rig's angles, every command on a rig collection (validate
// with the same-camera motion checks, convert, backproject, perturb-metadata,
// info), located errors, and objects riding on a moving object.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "backproject/cloud_io.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "generator/scene/world.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/json_io.h"
#include "libs/exr/flat_image.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

using testing::PlanText;

// A 2 m cube centred on the origin on flat ground: its top face is z = 2.
const char* kCubeScene =
    "LSCENE = ONE(W) ONE(CUBE)\n"
    "W = terrain{size:[60,60]}\n"
    "CUBE = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-0.01,-0.01,-10],[0.01,"
    "0.01,10]]}}\n";

// A stereo pair 0.5 m apart along the platform's x (east on a nadir path)
// plus a narrower, smaller third camera (a multispectral-like channel),
// flying 1 m east at 5 m/s and 10 fps, 20 m up: 3 time steps.
const char* kStereoCapture =
    "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
    "CO = camera{csettings:{fov:60,res:[96,72],fps:10},targets:[CUBE],\n"
    "  rig:{left:{position:[-0.25,0,0]},right:{position:[0.25,0,0]},\n"
    "       nir:{position:[0,0.1,0],csettings:{fov:40,res:[48,36]}}}}\n"
    "P = path{waypoints:{points:[[-0.5,0,20],[0.5,0,20]],speed:5}}\n"
    "CL = collection{CO:{move:[P]}}\n";

Eigen::Vector3d Centre(const Rigid3d& cam_from_world) {
  return CameraCenterInWorld(cam_from_world);
}

TEST(Rig, PlanHasAFramePerCameraPerStepSharingTimeAndWorld) {
  const Plan plan = PlanText(kCubeScene, kStereoCapture);
  ASSERT_TRUE(plan.rig);
  ASSERT_EQ(plan.rig->cameras.size(), 3u);
  ASSERT_EQ(plan.frames.size(), 9u);
  const char* names[] = {"left", "right", "nir"};
  for (size_t k = 0; k < plan.frames.size(); ++k) {
    const PlannedFrame& f = plan.frames[k];
    EXPECT_EQ(f.index, static_cast<int64_t>(k));
    EXPECT_EQ(f.step, static_cast<int64_t>(k / 3));
    EXPECT_EQ(*f.rig_camera, names[k % 3]);
    EXPECT_DOUBLE_EQ(f.time, static_cast<double>(k / 3) / 10);
    // Each camera is its own shot stream: the shot starts at its first frame.
    EXPECT_EQ(f.shot, static_cast<int64_t>(k % 3));
  }
  // Intrinsics per camera.
  EXPECT_EQ(plan.frames[0].camera.width, 96);
  EXPECT_EQ(plan.frames[2].camera.width, 48);
  EXPECT_NEAR(plan.frames[2].camera.HorizontalFovDeg(), 40, 1e-9);
  for (int step = 0; step < 3; ++step) {
    const Eigen::Vector3d left = Centre(plan.frames[3 * step].cam_from_world);
    const Eigen::Vector3d right = Centre(plan.frames[3 * step + 1].cam_from_world);
    const Eigen::Vector3d nir = Centre(plan.frames[3 * step + 2].cam_from_world);
    // The baseline: 0.5 m east; the platform 0.5 m further each step.
    EXPECT_TRUE((right - left).isApprox(Eigen::Vector3d(0.5, 0, 0), 1e-9)) << right - left;
    EXPECT_NEAR(0.5 * (left + right).x(), -0.5 + 0.5 * step, 1e-9);
    // Platform y is image down = south on a nadir path.
    EXPECT_NEAR(nir.y(), -0.1, 1e-9);
    EXPECT_NEAR(left.z(), 20, 1e-9);
    // One world for the step: the cameras see the same objects.
    EXPECT_EQ(gen::WorldAt(plan, plan.frames[3 * step]).objects[0].position,
              gen::WorldAt(plan, plan.frames[3 * step + 1]).objects[0].position);
    // Smooth flight velocity per camera (no rotation: the platform's).
    EXPECT_TRUE(
        plan.frames[3 * step + 1].camera_velocity->isApprox(Eigen::Vector3d(5, 0, 0), 1e-6));
  }
  // --frames: a sub-range is the same frames.
  const Plan part = PlanText(kCubeScene, kStereoCapture, 1, FrameRange{4, 7});
  ASSERT_EQ(part.frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(part.frames[i].index, plan.frames[4 + i].index);
    EXPECT_EQ(part.frames[i].rig_camera, plan.frames[4 + i].rig_camera);
    EXPECT_TRUE(part.frames[i].cam_from_world.translation.isApprox(
        plan.frames[4 + i].cam_from_world.translation));
  }
}

// The rig in the text notation and in the JSON form plans the same, and the
// plan's JSON form keeps it (generate --plan).
TEST(Rig, TextJsonAndPlanJsonAgree) {
  const SourceFile text_scene = ParseSource(kCubeScene, "s.lscene", false);
  const SourceFile text_capture = ParseSource(kStereoCapture, "c.lcap", false);
  const SourceFile json_scene = ParseSource(SourceToJson(text_scene).dump(2), "s.json", true);
  const SourceFile json_capture = ParseSource(SourceToJson(text_capture).dump(2), "c.json", true);
  const nlohmann::json full = PlanToJson(MakePlanFromSources(text_scene, &text_capture, 3));
  nlohmann::json from_text = full;
  nlohmann::json from_json = PlanToJson(MakePlanFromSources(json_scene, &json_capture, 3));
  for (auto* j : {&from_text, &from_json}) {
    j->erase("scene_source");
    j->erase("capture_source");
  }
  EXPECT_EQ(from_text, from_json);
  ASSERT_TRUE(from_text.contains("rig"));
  EXPECT_EQ(PlanToJson(PlanFromJson(full, "plan.json")), full);
}

TEST(Rig, NadirAndObliqueCamerasKeepTheirAnglesOnTheFlight) {
  const Plan plan = PlanText(
      kCubeScene,
      "LCAP = ONE(CO) ONE(P)\n"
      "CO = camera{csettings:{res:[64,48],fps:1},rig:{nadir:{},oblique:{attitude:[0,35,0]},"
      "side:{attitude:[90,0,0]}}}\n"
      "P = path{waypoints:{points:[[0,-20,40],[0,20,40]],speed:20}}\n");
  ASSERT_EQ(plan.frames.size(), 9u);
  for (size_t k = 0; k < plan.frames.size(); k += 3) {
    auto axis = [&](size_t i) -> Eigen::Vector3d {  // optical axis in the world
      return plan.frames[i].cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
    };
    const double deg = 180 / M_PI;
    EXPECT_NEAR(std::acos(-axis(k).z()) * deg, 0, 1e-9);       // nadir
    EXPECT_NEAR(std::acos(-axis(k + 1).z()) * deg, 35, 1e-9);  // 35 deg off nadir...
    EXPECT_GT(axis(k + 1).y(), 0);                             // ... towards the image top (north)
    EXPECT_NEAR(std::acos(axis(k).dot(axis(k + 2))) * deg, 0, 1e-9);  // roll: about the view
    // The rolled camera's image x is the nadir camera's image y.
    const Eigen::Vector3d side_x =
        plan.frames[k + 2].cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d nadir_y =
        plan.frames[k].cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitY();
    EXPECT_NEAR(side_x.dot(nadir_y), 1, 1e-9);
  }
}

TEST(Rig, MisuseIsALocatedError) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"CO = camera{rig:{left:{fps:3}}}\n", "unknown key 'fps'"},
      {"CO = camera{rig:{left:{csettings:{fps:3}}}}\n", "the platform's"},
      {"CO = camera{rig:{left:{position:[0,0]}}}\n", "position is [x, y, z]"},
      {"CO = camera{rig:{left:{position:[[0,1],0,0]}}}\n", "a rig offset is a number"},
      {"CO = camera{rig:{\"a b\":{}}}\n", "rig camera name"},
      {"CO = camera{rig:[left]}\n", "a rig names its cameras"},
      {"CO = camera{}\nC2 = camera{}\n", "several cameras on one platform are a rig"},
  };
  for (const auto& [camera, message] : cases) {
    try {
      PlanText(kCubeScene, "LCAP = ONE(P)\nP = path{waypoints:[[0,0,30]]}\n" + camera);
      ADD_FAILURE() << "accepted: " << camera;
    } catch (const Error& e) {
      EXPECT_NE(e.message().find(message), std::string::npos) << e.message();
      EXPECT_GE(e.location().line, 3) << e.location().ToString();
    }
  }
}

// Objects standing ON a moving object ride with it (docs/languages.md,
// "Scene changes keep the placement").
TEST(Rig, ObjectsOnAMovedObjectRideWithIt) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(CAR) ONE(CRATE)\n"
      "W = terrain{size:[100,100]}\n"
      "CAR = object{class:cube,extent:[4,2,1],position:{ON:W,within:[[-2,-1,-10],[2,1,10]]}}\n"
      "CRATE = object{class:cube,extent:[0.5,0.5,0.5],position:{ON:CAR,"
      "within:[[0.5,0.2,-10],[1.0,0.7,10]]}}\n";
  const std::string capture =
      "LCAP = ONE(CO) ONE(P) ONE(ROAD) ONE(CL)\n"
      "CO = camera{csettings:{res:[64,48],fps:10}}\n"
      "P = path{waypoints:[[0,0,30],[0,0,30],[0,0,30],[0,0,30],[0,0,30]]}\n"
      "ROAD = path{waypoints:{points:[[0,0,0],[0,10,0]],speed:10}}\n"
      "CL = collection{CO:{move:[P]},CAR:{after:1,move:[ROAD],heading:true}}\n";
  const Plan plan = PlanText(scene, capture);
  const PlannedObject& car0 = plan.objects[0];
  const PlannedObject& crate0 = plan.objects[1];
  ASSERT_EQ(crate0.symbol, "CRATE");
  EXPECT_NEAR(crate0.position.z(), 1.25, 1e-9);  // on the car's top
  for (const PlannedFrame& f : plan.frames) {
    const gen::WorldState world = gen::WorldAt(plan, f);
    const gen::ObjectState& car = world.objects[0];
    const gen::ObjectState& crate = world.objects[1];
    // The crate keeps its place on the car: the car's rigid motion applied.
    const Eigen::Matrix3d turn = car.world_from_object * car0.world_from_object.transpose();
    const Eigen::Vector3d expected = car.position + turn * (crate0.position - car0.position);
    EXPECT_TRUE(crate.position.isApprox(expected, 1e-9))
        << f.index << ": " << crate.position.transpose() << " vs " << expected.transpose();
    EXPECT_TRUE(crate.world_from_object.isApprox(turn * crate0.world_from_object, 1e-9));
    EXPECT_TRUE(crate.velocity.isApprox(car.velocity) || car.velocity.isZero()) << f.index;
    if (f.index >= 2) {
      // From frame 2 (after frame 1), 10 m/s at 10 fps: 1 m per frame.
      EXPECT_NEAR(car.position.y(), (f.index - 2) * 1.0, 1e-9);
      EXPECT_NEAR(crate.velocity.y(), 10, 1e-9);
    }
  }
}

std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The stereo rig end to end: generate, validate, the disparity of the cube's
// top against fx * baseline / depth, convert, backproject, perturb, info.
TEST(Rig, StereoCollectionEndToEnd) {
  testing::TempDir dir;
  std::ofstream(dir / "s.lscene") << kCubeScene;
  std::ofstream(dir / "c.lcap") << kStereoCapture;
  const std::string out = (dir / "out").string();
  const std::string lsds = testing::LsdsBinary();
  const auto generated =
      testing::RunCommandLine(lsds + " generate " + (dir / "s.lscene").string() + " " +
                              (dir / "c.lcap").string() + " -o " + out + " --spp 1 -q");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  const auto validated = testing::RunCommandLine(lsds + " validate " + out + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;

  const auto collection = nlohmann::json::parse(Slurp(dir / "out" / "collection.json"));
  ASSERT_EQ(collection["rig"]["cameras"].size(), 3u);
  EXPECT_EQ(collection["rig"]["cameras"][1]["name"], "right");
  const auto& frames = collection["frames"];
  ASSERT_EQ(frames.size(), 9u);
  EXPECT_EQ(frames[4]["rig_camera"], "right");
  EXPECT_EQ(frames[4]["step"], 1);
  EXPECT_EQ(frames[4]["files"]["depth"], "depth/000004_right.exr");
  // Stereo geometry per step: every left pixel centre on the cube's top (its
  // world position from the layer) projects into the right camera at the
  // disparity fx * B / Z to the left, and the right camera sees the same
  // surface point there.
  const double baseline = 0.5, depth_z = 18;  // 20 m up, top at z = 2
  for (int step = 0; step < 3; ++step) {
    const auto& left = frames[3 * step];
    const auto& right = frames[3 * step + 1];
    const double fx = left["camera"]["fx"];
    const int width = left["camera"]["width"], height = left["camera"]["height"];
    // World position through the collection reader: either storage layout.
    const CollectionReader reader(dir / "out");
    const exr::FlatImage lw = reader.ReadFlatLayer(
        FrameFromJson(left, "collection.json", ""), "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage ld =
        exr::ReadFlatExr(dir / "out" / left["files"]["depth"].get<std::string>(), {"Z"});
    const exr::FlatImage rw = reader.ReadFlatLayer(
        FrameFromJson(right, "collection.json", ""), "worldposition", {"X", "Y", "Z"});
    const Frame right_frame = FrameFromJson(right, "collection.json", "");
    const Eigen::Vector3d right_centre =
        CameraCenterInWorld(Rigid3d(Eigen::Quaterniond(right_frame.camera.cam_from_world_rotation),
                                    right_frame.camera.cam_from_world_translation));
    const double right_fx = right["camera"]["fx"], right_cx = right["camera"]["cx"];
    int on_top = 0;
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i) {
        const size_t p = static_cast<size_t>(j) * width + i;
        if (std::abs(lw.Get("Z").floats[p] - 2.0f) > 1e-4f) continue;  // not the cube's top
        ++on_top;
        EXPECT_NEAR(ld.Get("Z").floats[p], depth_z, 1e-4);
        // The right camera: x_r = x_l - B at the same depth (nadir, east).
        const double x_world = lw.Get("X").floats[p];
        const double u_right = right_fx * (x_world - right_centre.x()) / depth_z + right_cx;
        const double u_left = i + 0.5;
        EXPECT_NEAR(u_left - u_right, fx * baseline / depth_z, 2e-3) << i << "," << j;
        // And it sees that point (to within its pixel's footprint).
        const int ri = static_cast<int>(std::floor(u_right));
        if (ri < 0 || ri >= width) continue;
        const size_t q = static_cast<size_t>(j) * width + ri;
        if (std::abs(rw.Get("Z").floats[q] - 2.0f) > 1e-4f) continue;  // the edge of the top
        EXPECT_NEAR(rw.Get("X").floats[q], x_world, depth_z / fx + 1e-3);
        EXPECT_NEAR(rw.Get("Y").floats[q], lw.Get("Y").floats[p], 1e-4);
      }
    EXPECT_GT(on_top, 20) << "the cube's top is in view";
  }

  // convert: one image per frame, unique names with the camera.
  const auto converted = testing::RunCommandLine(lsds + " convert " + out + " --to coco -o " +
                                                 (dir / "coco").string());
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir / "coco"))
    if (entry.path().parent_path().parent_path().filename() == "images")
      names.insert(entry.path().filename().string());
  EXPECT_EQ(names.size(), 9u);
  EXPECT_TRUE(names.count("000004_right.png")) << *names.begin();
  int annotations = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir / "coco"))
    if (entry.path().extension() == ".json") {
      const auto coco = nlohmann::json::parse(Slurp(entry.path()));
      if (!coco.contains("images")) continue;
      for (const auto& image : coco["images"])
        EXPECT_TRUE(names.count(image["file_name"].get<std::string>())) << image;
      annotations += static_cast<int>(coco["annotations"].size());
    }
  EXPECT_EQ(annotations, 9);  // the cube in every frame

  // backproject: per-frame clouds named per camera; the cube's top points
  // of the left and right camera coincide.
  const auto clouds = testing::RunCommandLine(
      lsds + " backproject " + out + " --check --format ply -o " + (dir / "clouds").string());
  ASSERT_EQ(clouds.exit_code, 0) << clouds.output;
  const pointcloud::PointCloud left = pointcloud::ReadCloud(dir / "clouds" / "000000_left.ply");
  const pointcloud::PointCloud right = pointcloud::ReadCloud(dir / "clouds" / "000001_right.ply");
  std::vector<Eigen::Vector3d> right_top;
  for (const pointcloud::CloudPoint& p : right.points)
    if (std::abs(p.z - 2.0f) < 1e-3f) right_top.emplace_back(p.x, p.y, p.z);
  ASSERT_FALSE(right_top.empty());
  const double footprint = 18.0 / frames[0]["camera"]["fx"].get<double>();
  int matched = 0, tested = 0;
  for (const pointcloud::CloudPoint& p : left.points) {
    if (std::abs(p.z - 2.0f) > 1e-3f || std::abs(p.x) > 0.8 || std::abs(p.y) > 0.8) continue;
    ++tested;
    double best = 1e9;
    for (const Eigen::Vector3d& q : right_top)
      best = std::min(best, (q - Eigen::Vector3d(p.x, p.y, p.z)).norm());
    if (best <= footprint) ++matched;
  }
  EXPECT_GT(tested, 10);
  EXPECT_EQ(matched, tested);
  const auto fused = testing::RunCommandLine(
      lsds + " backproject " + out + " --fuse --voxel 0.05 -o " + (dir / "fused.ply").string());
  EXPECT_EQ(fused.exit_code, 0) << fused.output;

  // perturb-metadata: the cameras of one step share the platform's error.
  const auto perturbed =
      testing::RunCommandLine(lsds + " perturb-metadata " + out + " --sigma 1,1 --seed 7");
  ASSERT_EQ(perturbed.exit_code, 0) << perturbed.output;
  const auto metadata = nlohmann::json::parse(Slurp(dir / "out" / "metadata.perturbed-7.json"));
  for (int k = 0; k < 9; ++k)
    EXPECT_EQ(metadata["frames"][k]["error"], metadata["frames"][k - k % 3]["error"]) << k;
  EXPECT_NE(metadata["frames"][0]["error"], metadata["frames"][3]["error"]);
  const auto revalidated =
      testing::RunCommandLine(lsds + " validate " + out + " --fail-on warning");
  EXPECT_EQ(revalidated.exit_code, 0) << revalidated.output;

  // info names the rig.
  const auto info = testing::RunCommandLine(lsds + " info " + out + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const auto summary = nlohmann::json::parse(info.output.substr(info.output.find('{')));
  ASSERT_EQ(summary["cameras"]["rig"].size(), 3u);
  EXPECT_EQ(summary["cameras"]["rig"][2]["frames"], 3);
  EXPECT_EQ(summary["cameras"]["rig"][2]["resolution"], "48x36");

  // --frames of a rig gives the bytes of the single run's frames (motion
  // against the same camera one step back).
  const std::string part = (dir / "part").string();
  const auto partial = testing::RunCommandLine(lsds + " generate " + (dir / "s.lscene").string() +
                                               " " + (dir / "c.lcap").string() + " -o " + part +
                                               " --spp 1 -q --frames 4:5");
  ASSERT_EQ(partial.exit_code, 0) << partial.output;
  EXPECT_EQ(Slurp(dir / "part" / "motion" / "000004_right.exr"),
            Slurp(dir / "out" / "motion" / "000004_right.exr"));
}

// A rig frame whose platform pose disagrees with its step is an error.
TEST(Rig, ValidateFindsACameraOffTheRig) {
  testing::TempDir dir;
  std::ofstream(dir / "s.lscene") << kCubeScene;
  std::ofstream(dir / "c.lcap") << kStereoCapture;
  const std::string out = (dir / "out").string();
  const std::string lsds = testing::LsdsBinary();
  ASSERT_EQ(
      testing::RunCommandLine(lsds + " generate " + (dir / "s.lscene").string() + " " +
                              (dir / "c.lcap").string() + " -o " + out + " --spp 1 -q --frames 0:3")
          .exit_code,
      0);
  std::string text = Slurp(dir / "out" / "collection.json");
  auto collection = nlohmann::json::parse(text);
  collection["frames"][1]["camera"]["cam_from_world"]["translation"][0] =
      collection["frames"][1]["camera"]["cam_from_world"]["translation"][0].get<double>() + 0.2;
  collection["frames"][2]["rig_camera"] = "swir";
  std::ofstream(dir / "out" / "collection.json") << collection.dump();
  const auto validated = testing::RunCommandLine(lsds + " validate " + out);
  EXPECT_EQ(validated.exit_code, 1) << validated.output;
  EXPECT_NE(validated.output.find("structure.rig"), std::string::npos) << validated.output;
  EXPECT_NE(validated.output.find("puts the platform elsewhere"), std::string::npos)
      << validated.output;
  EXPECT_NE(validated.output.find("names no camera of the rig ('swir')"), std::string::npos)
      << validated.output;
}

}  // namespace
}  // namespace lsds
