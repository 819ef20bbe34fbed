// Requirements about placement and rigs (docs/languages.md, "Requirements and
// quotas"): relations to the camera checked per frame in the rendered truth,
// re-scatters that keep an object's LSCENE relations, LSCENE separation, and
// requirements with a camera rig (the step is the unit of redraw; all or any
// camera).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "generator/estimate.h"
#include "generator/lang/planner.h"
#include "generator/lang/requirements.h"
#include "generator/plan/plan_json.h"
#include "generator/plan/relations.h"
#include "libs/util/atomic_file.h"
#include "tests/build_paths.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

// Planned with the frame estimator (requirements need it).
Plan PlanText(const std::string& scene,
              const std::string& capture,
              uint64_t seed = 7,
              FrameRange frames = {}) {
  return testing::PlanText(scene, capture, seed, frames, gen::MakeFrameEstimatorFactory());
}

// Runs `lsds generate` and returns its output and collection.
std::pair<std::string, nlohmann::json> Generate(const testing::TempDir& dir,
                                                const std::string& scene,
                                                const std::string& capture,
                                                const std::string& name,
                                                const std::string& flags = "") {
  std::ofstream(dir / (name + ".lscene")) << scene;
  std::ofstream(dir / (name + ".lcap")) << capture;
  const auto r = testing::RunCommandLine(testing::LsdsBinary() + " generate " +
                                         (dir / (name + ".lscene")).string() + " " +
                                         (dir / (name + ".lcap")).string() + " -o " +
                                         (dir / name).string() + " --spp 1 --seed 3 " + flags);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return {r.output, nullptr};
  std::ifstream in(dir / name / "collection.json");
  return {r.output, nlohmann::json::parse(in)};
}

Rigid3d PoseOf(const nlohmann::json& frame) {
  Rigid3d pose;
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = frame["camera"]["cam_from_world"]["rotation"][i][j];
  pose.rotation = Eigen::Quaterniond(r);
  for (int i = 0; i < 3; ++i)
    pose.translation[i] = frame["camera"]["cam_from_world"]["translation"][i];
  return pose;
}

const nlohmann::json* Truth(const nlohmann::json& frame, const std::string& name) {
  for (const auto& o : frame["objects"])
    if (o["name"] == name) return &o;
  return nullptr;
}

// A target on flat ground whose heading (+x) is drawn.
const char* kScene =
    "LSCENE = ONE(W) ONE(T)\n"
    "W = terrain{size:[80,80]}\n"
    "T = object{class:cube,extent:[3,1.5,1],rotation:[0,0,[0,360]],"
    "position:{ON:W,within:[[-1,-1,-9],[1,1,9]]}}\n";

std::string NadirCapture(int count, const std::string& demand, const std::string& res = "[32,24]") {
  return "LCAP = ONE(CO) ONE(R) ONE(REQ)\n"
         "CO = camera{csettings:{fov:60,res:" +
         res +
         "},targets:[T]}\n"
         "R = path{random:{count:" +
         std::to_string(count) + ",x:[-8,8],y:[-8,8],altitude:30,off_nadir:0,yaw:[0,360]}}\n" +
         demand;
}

TEST(CameraRelations, InFrontOfAndBehindTheCameraHoldInTheTruth) {
  // A nadir camera's heading is the image top: IN FRONT OF CAMERA puts the
  // target in the image's upper half, BEHIND in the lower half.
  testing::TempDir dir;
  for (const std::string relation : {"IN FRONT OF", "BEHIND"}) {
    const std::string name = relation == "BEHIND" ? "behind" : "front";
    const auto [output, collection] =
        Generate(dir,
                 kScene,
                 NadirCapture(8, "REQ = require{target:T," + relation + ":CAMERA,budget:100}\n"),
                 name);
    ASSERT_FALSE(collection.is_null());
    for (const auto& frame : collection["frames"]) {
      const nlohmann::json* t = Truth(frame, "T#1");
      ASSERT_NE(t, nullptr);
      Eigen::Vector3d centre;
      for (int i = 0; i < 3; ++i) centre[i] = (*t)["obb"]["center"][i];
      const Eigen::Vector3d in_camera = PoseOf(frame) * centre;
      const double cy = frame["camera"]["cy"];
      const double v = cy + in_camera.y() / in_camera.z() * frame["camera"]["fy"].get<double>();
      if (relation == "BEHIND")
        EXPECT_GT(v, cy) << frame["index"];
      else
        EXPECT_LT(v, cy) << frame["index"];
      EXPECT_TRUE(frame["requirements"]["achieved_met"].get<bool>());
      EXPECT_EQ(frame["requirements"]["checks"][0]["quantity"], "ahead_of_camera");
    }
    const auto validated = testing::RunCommandLine(testing::LsdsBinary() + " validate " +
                                                   (dir / name).string() + " --fail-on warning");
    EXPECT_EQ(validated.exit_code, 0) << validated.output;
  }
}

TEST(CameraRelations, FacingTheCameraTurnsNothingButPicksTheViews) {
  // The camera looks at the target from around it; FACING:{CAMERA:20} keeps
  // the views where the target's front (+x) points at the camera within 20
  // degrees.
  const std::string capture =
      "LCAP = ONE(CO) ONE(R) ONE(REQ)\n"
      "CO = camera{csettings:{fov:40,res:[32,24]},targets:[T]}\n"
      "R = path{point:{position:[[-25,-25,12],[25,25,20]],look_at:T,count:30}}\n";
  const Plan plan = PlanText(kScene, capture + "REQ = require{target:T,FACING:{CAMERA:20}}\n");
  const Eigen::Vector2d heading = HeadingOf(plan.objects[0].world_from_object);
  for (const PlannedFrame& f : plan.frames) {
    const Eigen::Vector2d to_camera =
        (CameraCenterInWorld(f.cam_from_world) - plan.objects[0].position).head<2>().normalized();
    EXPECT_LT(std::acos(heading.dot(to_camera)) * 180 / M_PI, 20 + 1e-9) << f.index;
    EXPECT_TRUE(f.requirements->at("met").get<bool>());
  }
  // The control: the same draws without the requirement face it rarely.
  const Plan free = PlanText(kScene, capture + "REQ = require{altitude:[0,999]}\n");
  int facing = 0;
  for (const PlannedFrame& f : free.frames) {
    const Eigen::Vector2d to_camera =
        (CameraCenterInWorld(f.cam_from_world) - free.objects[0].position).head<2>().normalized();
    facing += std::acos(heading.dot(to_camera)) * 180 / M_PI < 20;
  }
  EXPECT_LT(facing, 10);
  // VISIBLE FROM:CAMERA and NEAR:{CAMERA:m} are bounds too.
  const Plan near = PlanText(
      kScene,
      capture + "REQ = require{target:T,NEAR:{CAMERA:22},VISIBLE FROM:CAMERA,budget:200}\n");
  for (const PlannedFrame& f : near.frames) {
    EXPECT_LE((CameraCenterInWorld(f.cam_from_world) - near.objects[0].position).norm(), 22);
    EXPECT_TRUE(f.requirements->at("met").get<bool>());
  }
}

TEST(CameraRelations, BadInputIsALocatedError) {
  for (const auto& [demand, expected] : std::vector<std::pair<std::string, std::string>>{
           {"REQ = require{target:T,FACING:T}\n", "relation is to the camera"},
           {"REQ = require{FACING:CAMERA}\n", "needs target:OBJECT"},
           {"REQ = require{target:T,VISIBLE FROM:{CAMERA:3}}\n", "takes no number"},
           {"REQ = require{target:T,BEHIND:{CAMERA:-1}}\n", "c.lcap:4:"}}) {
    try {
      PlanText(kScene, NadirCapture(2, demand));
      ADD_FAILURE() << demand;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

// A reference facing +x at the origin and clutter that must stay NEAR and
// BEHIND it, turned to FACE it, re-scattered on every frame.
const char* kRelationScene =
    "LSCENE = ONE(W) ONE(REF) MANY(C, 4)\n"
    "W = terrain{size:[80,80]}\n"
    "REF = object{class:cube,extent:[2,1,1],position:{ON:W,within:[[-0.1,-0.1,-9],[0.1,0.1,9]]}}\n"
    "C = object{class:barrel,target:false,position:{ON:W,NEAR:{REF:8},BEHIND:REF,FACING:REF}}\n";

TEST(Rescatter, KeepsTheObjectsRelations) {
  const std::string capture =
      "LCAP = ONE(CO) ONE(R) ONE(CL)\n"
      "CO = camera{csettings:{res:[32,24]},targets:[REF]}\n"
      "R = path{random:{count:40,x:[-5,5],y:[-5,5],altitude:40}}\n"
      "CL = collection{CO:{move:[R]},C:{during:R,rescatter:true}}\n";
  const SourceFile s = ParseSource(kRelationScene, "s.lscene", false);
  const SourceFile c = ParseSource(capture, "c.lcap", false);
  const Plan plan = MakePlanFromSources(s, &c, 7);
  int moved = 0;
  for (const PlannedFrame& f : plan.frames)
    for (const ObjectChange& change : f.changes) {
      if (change.object.rfind("C#", 0) != 0 || !change.position) continue;
      const Eigen::Vector3d& p = *change.position;
      ++moved;
      EXPECT_LE(p.head<2>().norm(), 8 + 1e-9) << f.index << " " << change.object;  // NEAR
      EXPECT_LT(p.x(), 0) << f.index << " " << change.object;                      // BEHIND
      if (change.world_from_object) {  // FACING: its heading points at REF
        const Eigen::Vector2d heading = HeadingOf(*change.world_from_object);
        EXPECT_NEAR(heading.dot(-p.head<2>().normalized()), 1, 1e-9);
      }
    }
  EXPECT_GE(moved, 40 * 4);
}

TEST(Separation, KeepsAFreeGapAroundEveryObjectAndAcrossRescatters) {
  auto scene = [](const std::string& separation) {
    return "LSCENE = ONE(W) MANY(B, 12)\n"
           "W = terrain{size:[80,80]}\n"
           "B = object{class:cube,extent:[1,1,1]," +
           separation + "position:{ON:W,within:[[-12,-12,-9],[12,12,9]]}}\n";
  };
  const std::string capture =
      "LCAP = ONE(CO) ONE(R) ONE(CL)\n"
      "CO = camera{csettings:{res:[32,24]}}\n"
      "R = path{random:{count:5,x:[-5,5],y:[-5,5],altitude:40}}\n"
      "CL = collection{CO:{move:[R]},B:{during:R,rescatter:true}}\n";
  auto closest_gap = [](const std::vector<OrientedBox>& boxes) {
    // Unit cubes without turns: the gap is the largest per-axis separation.
    double closest = 1e9;
    for (size_t i = 0; i < boxes.size(); ++i)
      for (size_t j = 0; j < i; ++j) {
        const Eigen::Vector3d d = (boxes[i].center - boxes[j].center).cwiseAbs();
        closest = std::min(closest, std::max(d.x(), d.y()) - 1.0);
      }
    return closest;
  };
  auto boxes_of = [](const Plan& plan, const PlannedFrame* f) {
    std::map<std::string, OrientedBox> boxes;
    for (const PlannedObject& o : plan.objects)
      boxes[o.name] = {o.position, 0.5 * o.extent, o.world_from_object};
    if (f)
      for (const ObjectChange& c : f->changes)
        if (c.position) boxes[c.object].center = *c.position;
    std::vector<OrientedBox> v;
    for (const auto& [name, b] : boxes) v.push_back(b);
    return v;
  };
  const SourceFile c = ParseSource(capture, "c.lcap", false);
  const SourceFile spaced = ParseSource(scene("separation:2.5,"), "s.lscene", false);
  const Plan plan = MakePlanFromSources(spaced, &c, 7);
  ASSERT_EQ(plan.objects.size(), 12u);
  EXPECT_GE(closest_gap(boxes_of(plan, nullptr)), 2.5);
  for (const PlannedFrame& f : plan.frames) EXPECT_GE(closest_gap(boxes_of(plan, &f)), 2.5);
  // The control: without it, some boxes come closer.
  const SourceFile dense = ParseSource(scene(""), "s.lscene", false);
  EXPECT_LT(closest_gap(boxes_of(MakePlanFromSources(dense, &c, 7), nullptr)), 2.5);
  // Misuse is located.
  try {
    MakePlanFromSources(ParseSource(scene("overlap:true,separation:2,"), "s.lscene", false), &c, 7);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.lscene:3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs overlap:false"), std::string::npos) << e.what();
  }
}

// A nadir camera and one 20 degrees forward on random poses.
std::string RigCapture(int count, const std::string& demand) {
  return "LCAP = ONE(CO) ONE(R) ONE(REQ)\n"
         "CO = camera{csettings:{fov:50,res:[32,24]},targets:[T],"
         "rig:{nadir:{},oblique:{attitude:[0,20,0]}}}\n"
         "R = path{random:{count:" +
         std::to_string(count) + ",x:[-15,15],y:[-15,15],altitude:25,yaw:[0,360]}}\n" + demand;
}

TEST(RigRequirements, EveryCameraOfAStepMeetsTheDemandInTheTruth) {
  testing::TempDir dir;
  const std::string capture = RigCapture(5, "REQ = require{target:T,in_frame:[1,1],budget:300}\n");
  const auto [output, single] = Generate(dir, kScene, capture, "all");
  ASSERT_FALSE(single.is_null());
  ASSERT_EQ(single["frames"].size(), 10u);
  EXPECT_NE(output.find("5 steps with a demand, 5 met by estimate, 5 met in the rendered truth"),
            std::string::npos)
      << output;
  int redrawn = 0;
  for (const auto& frame : single["frames"]) {
    const nlohmann::json* t = Truth(frame, "T#1");
    ASSERT_NE(t, nullptr) << frame["index"];
    EXPECT_EQ((*t)["in_frame"].get<double>(), 1.0) << frame["index"];  // the truth itself
    EXPECT_EQ(frame["requirements"]["step"], frame["step"]);
    EXPECT_TRUE(frame["requirements"]["step_met"].get<bool>());
    redrawn += frame["requirements"]["attempts"].get<int>() > 1;
  }
  EXPECT_GT(redrawn, 0);
  // Both cameras of a step moved together: one platform pose per step.
  for (size_t k = 0; k + 1 < single["frames"].size(); k += 2)
    EXPECT_EQ(single["frames"][k]["requirements"]["attempts"],
              single["frames"][k + 1]["requirements"]["attempts"]);
  const auto validated = testing::RunCommandLine(testing::LsdsBinary() + " validate " +
                                                 (dir / "all").string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  // --frames that cut a step in two, and shards, equal the single run.
  for (const auto& [name, flags] : std::vector<std::pair<std::string, std::string>>{
           {"range", "--frames 3:8"}, {"shard", "--shard 1/2"}}) {
    const auto part = Generate(dir, kScene, capture, name, flags).second;
    ASSERT_FALSE(part.is_null());
    ASSERT_FALSE(part["frames"].empty());
    EXPECT_EQ(part["provenance"]["requirements"], single["provenance"]["requirements"]);
    for (const auto& frame : part["frames"]) {
      const size_t k = frame["index"];
      EXPECT_EQ(frame, single["frames"][k]) << name << " frame " << k;
      for (const auto& [layer, file] : frame["files"].items())
        EXPECT_TRUE(ReadFile(dir / name / file.get<std::string>()) ==
                    ReadFile(dir / "all" / file.get<std::string>()))
            << name << " " << file;
    }
  }
}

TEST(RigRequirements, AnyCameraIsEnoughWithCamerasAny) {
  const Plan all = PlanText(kScene, RigCapture(40, "REQ = require{target:T,in_frame:[1,1]}\n"));
  const Plan any =
      PlanText(kScene, RigCapture(40, "REQ = require{target:T,in_frame:[1,1],cameras:any}\n"));
  EXPECT_EQ(any.requirements["cameras"], "any");
  EXPECT_EQ(any.requirements["unit"], "step");
  int64_t all_attempts = 0, any_attempts = 0, one_camera_only = 0;
  for (size_t k = 0; k < any.frames.size(); k += 2) {
    const bool nadir = any.frames[k].requirements->at("met").get<bool>();
    const bool oblique = any.frames[k + 1].requirements->at("met").get<bool>();
    EXPECT_TRUE(nadir || oblique) << "step " << k / 2;
    EXPECT_TRUE(any.frames[k].requirements->at("step_met").get<bool>());
    one_camera_only += nadir != oblique;
    any_attempts += any.frames[k].requirements->at("attempts").get<int64_t>();
    EXPECT_TRUE(all.frames[k].requirements->at("met").get<bool>());
    EXPECT_TRUE(all.frames[k + 1].requirements->at("met").get<bool>());
    all_attempts += all.frames[k].requirements->at("attempts").get<int64_t>();
  }
  EXPECT_GT(one_camera_only, 0);          // any is weaker than all ...
  EXPECT_LT(any_attempts, all_attempts);  // ... and cheaper
}

TEST(RigRequirements, TheRigExampleTakesRequirementsAndAQuota) {
  // examples/time_of_day_movers: a nadir + oblique rig on a smooth flight
  // (no pose to redraw); the quota over the sun's elevation is met by the
  // light change the capture makes after step 2.
  const std::string dir = ::lsds::testing::ExamplesDir();
  const std::string lcap = ReadFile(dir + "/time_of_day_movers.lcap");
  const std::string lscene = ReadFile(dir + "/time_of_day_movers.lscene");
  std::string capture = lcap;
  capture.replace(capture.find("ONE(CL)"), 7, "ONE(CL) ONE(REQ) ONE(Q)");
  capture +=
      "REQ = require{target:TRUCK,in_frame:[0.5,1],cameras:any}\n"
      "Q = quota{quantity:sun_elevation,bins:[-90,10,90],weights:[1,1],budget:2}\n";
  const Plan plan = PlanText(lscene, capture, 1);
  ASSERT_TRUE(plan.rig);
  ASSERT_FALSE(plan.frames.empty());
  for (const PlannedFrame& f : plan.frames) {
    ASSERT_TRUE(f.requirements);
    EXPECT_EQ(f.requirements->at("step"), f.step);
  }
  EXPECT_EQ(plan.requirements["unit"], "step");
}

}  // namespace
}  // namespace lsds
