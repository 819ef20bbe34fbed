// Objects over time (docs/languages.md, "Objects that move", "Class swaps and
// re-scatters"): an object moving along a path at a known speed seen by a
// static camera (pose, velocity, box shift and motion vectors against their
// analytic values), class swaps from a frame on, and per-frame re-scatters by
// Algorithm 1 that keep the constraints and the overlap policy.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "generator/generate.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "generator/plan/terrain_height.h"
#include "generator/plan_source.h"
#include "generator/scene/builtin_meshes.h"
#include "generator/scene/world.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/oriented_box.h"
#include "libs/util/atomic_file.h"
#include "tests/generator/generate_validated.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

using testing::PlanText;

// A 2 x 1 x 1 m cube on flat ground, first at the origin.
const char* kCarScene =
    "LSCENE = ONE(W) ONE(CAR)\n"
    "W = terrain{size:[100,100]}\n"
    "CAR = object{class:cube,extent:[2,1,1],position:{ON:W,within:[[-1,-0.5,"
    "-10],[1,0.5,10]]}}\n";

// A static nadir camera 30 m up (one shot of identical waypoints) at 10 fps;
// the car drives east at 5 m/s from x = -4 to x = 4.
std::string CarCapture(int frames, const std::string& extra = "") {
  std::string waypoints;
  for (int k = 0; k < frames; ++k) waypoints += std::string(k ? "," : "") + "[0,0,30]";
  return "LCAP = ONE(CO) ONE(P) ONE(DRIVE) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[120,90],fps:10},targets:[CAR]}\n"
         "P = path{waypoints:[" +
         waypoints +
         "]}\n"
         "DRIVE = path{waypoints:{points:[[-4,0,0],[4,0,0]],speed:5}}\n"
         "CL = collection{CO:{move:[P]},CAR:{move:[DRIVE]" +
         extra + "}}\n";
}

// A truck driving 160 m along a road at 2 m/s, filmed for 81 frames at 1 fps from a fixed point
// 40 m up beside the road (look_at) and from a hemi around it (its centre is the first target).
TEST(MovingObjects, LookAtAndHemiCentresFollowTheTargetOnEveryFrame) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(TRUCK)\n"
      "W = terrain{size:[400,400]}\n"
      "TRUCK = object{class:truck,extent:[8,2.5,3],position:{ON:W,within:[[-84,-1.25,-10],"
      "[-76,1.25,10]]}}\n";
  const std::string road = "ROAD = path{waypoints:{points:[[-80,0,1.5],[80,0,1.5]],speed:2}}\n";
  for (const std::string& camera_path :
       {std::string("P = path{create point:{position:[0,-30,40],look_at:TRUCK,count:81}}\n"),
        std::string("P = path{create hemi:{cam radius:[60,60,1],obj angle:[0,360,81],"
                    "cam angle:[50,50,1]}}\n")}) {
    const Plan plan =
        PlanText(scene,
                 "LCAP = ONE(CO) ONE(P) ONE(ROAD) ONE(CL)\n"
                 "CO = camera{csettings:{fov:40,res:[320,240],fps:1},targets:[TRUCK]}\n" +
                     camera_path + road + "CL = collection{CO:{move:[P]},TRUCK:{move:[ROAD]}}\n");
    ASSERT_EQ(plan.frames.size(), 81u);
    double travelled = 0;
    for (const PlannedFrame& f : plan.frames) {
      const gen::ObjectState truck = gen::WorldAt(plan, f).objects[0];
      travelled = truck.position.x() - plan.objects[0].position.x();
      const Eigen::Vector3d in_cam = f.cam_from_world * truck.position;
      ASSERT_GT(in_cam.z(), 0) << camera_path << " frame " << f.index;
      const Eigen::Vector2d pixel = f.camera.ImageFromCam(in_cam);
      // The camera aims at the truck's centre: it projects to the principal point.
      EXPECT_NEAR(pixel.x(), f.camera.cx, 1e-6) << camera_path << " frame " << f.index;
      EXPECT_NEAR(pixel.y(), f.camera.cy, 1e-6) << camera_path << " frame " << f.index;
    }
    EXPECT_NEAR(travelled, 160, 1e-6);  // it did drive the whole road
  }
}

TEST(MovingObjects, PoseAndVelocityFollowThePathAtItsSpeed) {
  const Plan plan = PlanText(kCarScene, CarCapture(20));
  ASSERT_EQ(plan.frames.size(), 20u);
  for (const PlannedFrame& f : plan.frames) {
    const gen::WorldState world = gen::WorldAt(plan, f);
    const gen::ObjectState& car = world.objects[0];
    // 8 m at 5 m/s: 1.6 s, then it stays at the end, at rest.
    const double t = f.time;
    const double x = t < 1.6 ? -4 + 5 * t : 4;
    EXPECT_NEAR(car.position.x(), x, 1e-9) << f.index;
    EXPECT_NEAR(car.position.y(), 0, 1e-9);
    EXPECT_NEAR(car.position.z(), 0.5, 1e-9);  // its base on the ground
    const Eigen::Vector3d v = t < 1.6 ? Eigen::Vector3d(5, 0, 0) : Eigen::Vector3d::Zero();
    EXPECT_TRUE(car.velocity.isApprox(v) || (v.isZero() && car.velocity.isZero()))
        << f.index << ": " << car.velocity.transpose();
    EXPECT_EQ(f.shot, 0);
  }
  // The plan's JSON form keeps the velocity.
  const nlohmann::json j = PlannedFrameToJson(plan.frames[3]);
  bool found = false;
  for (const auto& c : j["changes"])
    if (c.contains("velocity")) {
      found = true;
      EXPECT_EQ(c["velocity"], nlohmann::json({5.0, 0.0, 0.0}));
    }
  EXPECT_TRUE(found);
}

TEST(MovingObjects, HeadingLapsLegsAndHillsFollowThePath) {
  // A walker goes around a 10 m square twice (P2:2) then north along Q,
  // turning to its direction of travel, on hilly ground.
  const std::string scene =
      "LSCENE = ONE(W) ONE(WALKER)\n"
      "W = terrain{size:[100,100],height:{perlin:{amplitude:2}}}\n"
      "WALKER = object{class:person,position:{ON:W}}\n";
  const std::string capture =
      "LCAP = ONE(CO) ONE(P) ONE(SQ) ONE(Q) ONE(CL)\n"
      "CO = camera{csettings:{fps:2}}\n"
      "P = path{waypoints:{points:[[0,0,40],[0,60,40]],speed:1}}\n"
      "SQ = path{waypoints:{points:[[0,0,0],[10,0,0],[10,10,0],[0,10,0],[0,0,"
      "0]],speed:2}}\n"
      "Q = path{waypoints:{points:[[0,0,0],[0,20,0]],speed:4}}\n"
      "CL = collection{CO:{move:[P]},WALKER:{after:3,move:[SQ:2,Q],heading:"
      "true}}\n";
  const Plan plan = PlanText(scene, capture);
  // Lap: 40 m at 2 m/s = 20 s; two laps 40 s; then Q 5 s. Moving from frame
  // 4 (time 2 s) at 2 fps.
  for (const PlannedFrame& f : plan.frames) {
    const gen::ObjectState walker = gen::WorldAt(plan, f).objects[0];
    const double t = f.time - 2.0;
    Eigen::Vector2d expected;
    Eigen::Vector2d direction;
    if (t < 0) continue;
    if (t < 40) {
      const double s = std::fmod(t, 20.0) * 2;  // metres into the lap
      const int side = static_cast<int>(s / 10);
      const double u = s - 10 * side;
      const Eigen::Vector2d corners[5] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
      direction = (corners[side + 1] - corners[side]) / 10;
      expected = corners[side] + u * direction;
      EXPECT_NEAR(walker.velocity.head<2>().norm(), 2, 1e-9) << f.index;
    } else if (t < 45) {
      direction = {0, 1};
      expected = {0, 4 * (t - 40)};
      EXPECT_NEAR(walker.velocity.head<2>().norm(), 4, 1e-9) << f.index;
    } else {
      direction = {0, 1};
      expected = {0, 20};
      EXPECT_TRUE(walker.velocity.isZero()) << f.index;
    }
    EXPECT_NEAR(walker.position.x(), expected.x(), 1e-9) << f.index;
    EXPECT_NEAR(walker.position.y(), expected.y(), 1e-9) << f.index;
    // Standing on the hills, base on the ground.
    const double half_z = (walker.world_from_object.cwiseAbs() * (0.5 * walker.extent)).z();
    EXPECT_NEAR(walker.position.z() - half_z,
                TerrainHeight(plan.terrain, expected.x(), expected.y()),
                1e-9);
    // Its x axis points where it goes (at a corner either way).
    const Eigen::Vector3d forward = walker.world_from_object.col(0);
    const bool corner = t < 40 && std::abs(std::remainder(std::fmod(t, 20.0) * 2, 10.0)) < 1e-9;
    if (!corner) {
      EXPECT_NEAR(forward.head<2>().dot(direction), 1, 1e-9) << f.index;
    }
  }
  // Before its timing the walker is where the scene put it.
  EXPECT_EQ(gen::WorldAt(plan, plan.frames[3]).objects[0].position, plan.objects[0].position);
  // The vertical velocity is the slope along the motion: the numeric
  // derivative of the seated height.
  const PlannedFrame& f = plan.frames[10];
  const gen::ObjectState a = gen::WorldAt(plan, f).objects[0];
  const Eigen::Vector3d p = a.position, v = a.velocity;
  const double h = 1e-4;
  const double dz = (TerrainHeight(plan.terrain, p.x() + h * v.x(), p.y() + h * v.y()) -
                     TerrainHeight(plan.terrain, p.x() - h * v.x(), p.y() - h * v.y())) /
                    (2 * h);
  EXPECT_NEAR(v.z(), dz, 1e-5);
}

// A static nadir camera 30 m up for `frames` frames at `fps`, and the car's collection entry.
std::string StaticCameraCapture(int frames,
                                int fps,
                                const std::string& paths,
                                const std::string& car_entry) {
  std::string waypoints;
  for (int k = 0; k < frames; ++k) waypoints += std::string(k ? "," : "") + "[0,0,30]";
  return "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[120,90],fps:" +
         std::to_string(fps) + "},targets:[CAR]}\nP = path{waypoints:[" + waypoints + "]}\n" +
         paths + "CL = collection{CO:{move:[P]},CAR:{" + car_entry + "}}\n";
}

// Any path kind: a waypoint list and a grid's lawnmower rows are followed one point per frame, as
// the camera flies them; the velocity and heading are the segment's ahead, then at rest.
TEST(MovingObjects, AWaypointListOrAGridIsFollowedOnePointPerFrame) {
  const std::vector<std::pair<std::string, std::vector<Eigen::Vector2d>>> cases = {
      {"ROUTE = path{waypoints:[[0,0,0],[6,0,0],[6,8,0]]}\n", {{0, 0}, {6, 0}, {6, 8}}},
      {"ROUTE = path{increment point:{x:[-4,4,3],y:[0,4,2],altitude:0}}\n",
       {{-4, 0}, {0, 0}, {4, 0}, {4, 4}, {0, 4}, {-4, 4}}},
  };
  for (const auto& [route, knots] : cases) {
    const Plan plan =
        PlanText(kCarScene, StaticCameraCapture(8, 10, route, "move:[ROUTE],heading:true"));
    ASSERT_EQ(plan.frames.size(), 8u);
    for (const PlannedFrame& f : plan.frames) {
      const gen::ObjectState car = gen::WorldAt(plan, f).objects[0];
      const size_t j = std::min<size_t>(static_cast<size_t>(f.index), knots.size() - 1);
      EXPECT_EQ(car.position, Eigen::Vector3d(knots[j].x(), knots[j].y(), 0.5)) << route << f.index;
      if (j + 1 == knots.size()) {
        EXPECT_TRUE(car.velocity.isZero()) << route << f.index;
        continue;
      }
      const Eigen::Vector2d step = knots[j + 1] - knots[j];
      EXPECT_NEAR((car.velocity - Eigen::Vector3d(10 * step.x(), 10 * step.y(), 0)).norm(), 0, 1e-9)
          << route << f.index;
      // Heading per segment: the object's x axis along the segment ahead.
      EXPECT_NEAR(car.world_from_object.col(0).head<2>().dot(step.normalized()), 1, 1e-12)
          << route << f.index;
    }
  }
}

// With a speed the same polyline is driven at that speed: the position at time t is closed-form.
TEST(MovingObjects, AWaypointListAtASpeedIsAPolylineInTime) {
  const Plan plan =
      PlanText(kCarScene,
               StaticCameraCapture(40,
                                   10,
                                   "ROUTE = path{waypoints:[[0,0,0],[6,0,0],[6,8,0]]}\n",
                                   "move:[ROUTE],speed:5,heading:true"));
  for (const PlannedFrame& f : plan.frames) {
    const gen::ObjectState car = gen::WorldAt(plan, f).objects[0];
    const double t = f.time;  // 6 m east in 1.2 s, then 8 m north in 1.6 s
    Eigen::Vector3d p(6, 8, 0.5), v(0, 0, 0);
    if (t < 1.2 - 1e-12) {
      p = {5 * t, 0, 0.5};
      v = {5, 0, 0};
    } else if (t < 2.8 - 1e-12) {
      p = {6, 5 * (t - 1.2), 0.5};
      v = {0, 5, 0};
    }
    EXPECT_NEAR((car.position - p).norm(), 0, 1e-9) << f.index;
    EXPECT_NEAR((car.velocity - v).norm(), 0, 1e-9) << f.index;
    if (!v.isZero()) {
      EXPECT_NEAR(car.world_from_object.col(0).dot(v.normalized()), 1, 1e-12) << f.index;
    }
  }
}

// A hemi ring is an orbit: two laps of a circle of radius 10 about (2, 1) at pi m/s (20 s a lap),
// the position, velocity and heading those of uniform circular motion.
TEST(MovingObjects, AHemiRingIsAnOrbitInClosedForm) {
  const Plan plan = PlanText(
      kCarScene,
      StaticCameraCapture(90,
                          2,
                          "ORBIT = path{create hemi:{cam radius:[10,10,1],obj angle:[0,360,5],"
                          "cam angle:[0,0,1],center:[2,1,0]}}\n",
                          "move:[ORBIT:2],speed:3.141592653589793,heading:true"));
  ASSERT_EQ(plan.frames.size(), 90u);
  for (const PlannedFrame& f : plan.frames) {
    const gen::ObjectState car = gen::WorldAt(plan, f).objects[0];
    const double t = f.time;
    if (t >= 40) {  // at rest where the second lap ends
      EXPECT_NEAR((car.position - Eigen::Vector3d(12, 1, 0.5)).norm(), 0, 1e-9) << f.index;
      EXPECT_TRUE(car.velocity.isZero()) << f.index;
      continue;
    }
    const double a = M_PI * t / 10;  // rad
    EXPECT_NEAR(
        (car.position - Eigen::Vector3d(2 + 10 * std::cos(a), 1 + 10 * std::sin(a), 0.5)).norm(),
        0,
        1e-9)
        << f.index;
    const Eigen::Vector3d v = M_PI * Eigen::Vector3d(-std::sin(a), std::cos(a), 0);
    EXPECT_NEAR((car.velocity - v).norm(), 0, 1e-9) << f.index;
    EXPECT_NEAR(car.world_from_object.col(0).dot(v.normalized()), 1, 1e-12) << f.index;
  }
}

// Generated and validated as a user does: the gate (--fail-on warning) passes with the object
// orbiting at 2 fps, and the collection's truth is the closed form.
TEST(MovingObjects, AnOrbitingObjectValidates) {
  testing::TempDir dir;
  const auto collection = testing::GenerateValidated(
      dir,
      kCarScene,
      StaticCameraCapture(6,
                          2,
                          "ORBIT = path{create hemi:{cam radius:[6,6,1],obj angle:[0,360,5],"
                          "cam angle:[0,0,1],center:[0,0,0]}}\n",
                          "move:[ORBIT],speed:1.5707963267948966,heading:true"));
  const auto& frames = collection["frames"];
  ASSERT_EQ(frames.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    const auto& car = frames[k]["objects"][0];
    const double angle = M_PI / 12 * (k * 0.5);  // pi/2 m/s on radius 6: pi/12 rad/s
    EXPECT_NEAR(car["obb"]["center"][0].get<double>(), 6 * std::cos(angle), 1e-9) << k;
    EXPECT_NEAR(car["obb"]["center"][1].get<double>(), 6 * std::sin(angle), 1e-9) << k;
    EXPECT_NEAR(car["velocity"][0].get<double>(), -M_PI / 2 * std::sin(angle), 1e-9) << k;
    EXPECT_NEAR(car["velocity"][1].get<double>(), M_PI / 2 * std::cos(angle), 1e-9) << k;
  }
}

TEST(MovingObjects, MisuseIsALocatedError) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"CL = collection{CO:{move:[P]},CAR:{move:[NOPE]}}\n", "not a path"},
      {"CL = collection{CO:{move:[P]},CAR:{move:[DRIVE],speed:3}}\n", "has its own speed"},
      {"CL = collection{CO:{move:[P]},CAR:{speed:3}}\n", "add move"},
      {"CL = collection{CO:{move:[P]},CAR:{move:[P],speed:0}}\n", "speed must be"},
      {"CL = collection{CO:{move:[P]},CAR:{heading:true}}\n", "add move"},
      {"CL = collection{CO:{move:[P]},CAR:{move:[DRIVE],rescatter:true}}\n", "either moves"},
      {"CL = collection{CO:{move:[P]},CAR:{move:[DRIVE],offset:[1,0,0]}}\n",
       "position comes from its path"},
      {"CL = collection{CO:{move:[P]},CAR:{after:1,class:barel}}\n", "did you mean 'barrel'"},
  };
  for (const auto& [collection, message] : cases) {
    try {
      PlanText(kCarScene,
               "LCAP = ONE(P) ONE(DRIVE) ONE(CL)\n"
               "P = path{waypoints:[[0,0,30],[0,0,30]]}\n"
               "DRIVE = path{waypoints:{points:[[-4,0,0],[4,0,0]],speed:5}}\n" +
                   collection);
      ADD_FAILURE() << "accepted: " << collection;
    } catch (const Error& e) {
      EXPECT_NE(e.message().find(message), std::string::npos) << e.message();
      EXPECT_EQ(e.location().line, 4) << e.location().ToString();
    }
  }
}

// The camera sees the car at 30 m: its top face (z = 1) is 29 m away.
TEST(MovingObjects, BoxesVelocitiesAndMotionVectorsAreAnalytic) {
  testing::TempDir dir;
  const auto collection = testing::GenerateValidated(dir, kCarScene, CarCapture(4));
  const auto& frames = collection["frames"];
  ASSERT_EQ(frames.size(), 4u);
  const double fx = frames[0]["camera"]["fx"], cx = frames[0]["camera"]["cx"],
               cy = frames[0]["camera"]["cy"];
  const int width = frames[0]["camera"]["width"], height = frames[0]["camera"]["height"];
  // 0.5 m per frame at 29 m.
  const double shift_px = fx * 0.5 / 29.0;
  // Motion through the collection reader (whichever layout stores it).
  const CollectionReader reader(dir / "out");
  std::vector<Frame> truth;
  reader.ForEachFrame([&](const Frame& frame) { truth.push_back(frame); });
  ASSERT_EQ(truth.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(frames[k]["objects"].size(), 1u);
    const auto& car = frames[k]["objects"][0];
    EXPECT_EQ(car["velocity"], nlohmann::json({5.0, 0.0, 0.0}));
    EXPECT_NEAR(car["obb"]["center"][0].get<double>(), -4 + 0.5 * k, 1e-9);
    if (k == 0) continue;
    const auto& before = frames[k - 1]["objects"][0];
    // The projected box's left edge is the top face's (29 m away), its right
    // edge the bottom face's (30 m away; the car is left of the centre).
    EXPECT_NEAR(car["bbox_projected"][0].get<double>() - before["bbox_projected"][0].get<double>(),
                shift_px,
                1e-6);
    EXPECT_NEAR(car["bbox_projected"][2].get<double>() - before["bbox_projected"][2].get<double>(),
                fx * 0.5 / 30.0,
                1e-6);
    for (int c : {1, 3})
      EXPECT_NEAR(
          car["bbox_projected"][c].get<double>(), before["bbox_projected"][c].get<double>(), 1e-9);
    // The tight box moves by the same amount, to within a pixel.
    EXPECT_NEAR(car["bbox"][0].get<double>() - before["bbox"][0].get<double>(), shift_px, 1.0);
    // At the pixel under the top face's centre, the motion vector is the
    // projection difference: (shift, 0) pixels.
    const exr::FlatImage motion = reader.ReadFlatLayer(truth[k], "motion", {"X", "Y"});
    const int px =
        static_cast<int>(std::floor(cx + fx * car["obb"]["center"][0].get<double>() / 29.0));
    const int py = static_cast<int>(std::floor(cy));
    const size_t p = static_cast<size_t>(py) * width + px;
    EXPECT_NEAR(motion.Get("X").floats[p], 0.5 + 0.5 * shift_px / width, 1e-5);
    EXPECT_NEAR(motion.Get("Y").floats[p], 0.5, 1e-5);
    // The ground far from the car does not move.
    EXPECT_NEAR(motion.Get("X").floats[5], 0.5, 1e-6);
  }
  (void)height;
}

// A moving object covering a fifth of the image: the validator's motion
// cross-check carries its points with its box, so the collection is clean
// (checked against the camera motion alone, a fifth of the pixels would
// disagree).
TEST(MovingObjects, ALargeMovingObjectPassesTheMotionCrossCheck) {
  testing::TempDir dir;
  const auto collection =
      testing::GenerateValidated(dir,
                                 "LSCENE = ONE(W) ONE(CAR)\n"
                                 "W = terrain{size:[100,100]}\n"
                                 "CAR = object{class:cube,extent:[12,12,1],position:{ON:W}}\n",
                                 CarCapture(3));
  const auto& car = collection["frames"][1]["objects"][0];
  EXPECT_GT(car["visible_pixels"].get<double>(), 0.15 * 120 * 90);
}

// The case: cars swapped for trucks are truck-sized (8 x 2.5 x 3.2 m), not car-sized;
// each car has its shape's own size (builtin_meshes.h).
TEST(ClassSwaps, EachDrawnClassHasItsOwnBox) {
  const Plan plan = PlanText(
      "LSCENE = ONE(W) MANY(V, 12)\nW = terrain{size:[200,200]}\n"
      "V = object{class:car,overlap:true,position:{ON:W}}\n",
      "LCAP = ONE(CO) ONE(P) ONE(CL)\nCO = camera{}\n"
      "P = path{waypoints:[[0,0,150],[0,0,150]]}\n"
      "CL = collection{CO:{move:[P]},V:{after:0,class:{truck:0.5,car:0.5}}}\n");
  const gen::WorldState world = gen::WorldAt(plan, plan.frames[1]);
  std::map<std::string, int> drawn;
  for (const gen::ObjectState& v : world.objects) {
    ++drawn[v.asset];
    if (v.asset == "car") {  // the car family: one shape's own size
      bool own = false;
      for (const gen::CarShape& shape : gen::CarShapes()) own = own || v.extent == shape.size;
      EXPECT_TRUE(own) << v.planned->name << " " << v.extent.transpose();
    } else {
      EXPECT_EQ(v.extent, BuiltinClasses().at(v.asset)) << v.planned->name << " " << v.asset;
    }
    EXPECT_NEAR(v.position.z() - 0.5 * v.extent.z(), 0, 1e-9) << v.planned->name;  // grounded
  }
  EXPECT_GT(drawn["truck"], 0);
  EXPECT_GT(drawn["car"], 0);
}

TEST(ClassSwaps, AnObjectTakesAnotherClassFromAFrameOn) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(K) ONE(O) ONE(B)\n"
      "W = terrain{size:[60,60]}\nK = classes{debris:tire}\n"
      "O = object{class:barrel,position:{ON:W,within:[[-2,-2,-9],[2,2,9]]}}\n"
      "B = object{class:cube,position:{ON:W,within:[[8,8,-9],[12,12,9]]}}\n";
  const std::string capture =
      "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
      "CO = camera{csettings:{res:[96,72]},targets:[O,B:9]}\n"
      "P = path{waypoints:[[0,0,30],[0,0,30],[0,0,30],[0,0,30]]}\n"
      "CL = collection{CO:{move:[P]},O:{after:1,class:debris},"
      "B:{frame:3,class:{sphere:1}}}\n";
  const Plan plan = PlanText(scene, capture);
  std::map<std::string, uint32_t> ids;
  for (const ClassInfo& c : plan.classes) ids[c.name] = c.id;
  ASSERT_TRUE(ids.count("debris")) << "the swapped-in class joins the table";
  for (const PlannedFrame& f : plan.frames) {
    const gen::WorldState world = gen::WorldAt(plan, f);
    const gen::ObjectState& o = world.objects[0];
    const gen::ObjectState& b = world.objects[1];
    EXPECT_EQ(o.asset, f.index >= 2 ? "tire" : "barrel") << f.index;
    EXPECT_EQ(o.class_id, f.index >= 2 ? ids["debris"] : ids["barrel"]);
    // A swapped-in asset has its own size (the tire's 0.7 x 0.25 x 0.7 m, not the barrel's box),
    // its base still on the ground.
    const Eigen::Vector3d o_extent =
        f.index >= 2 ? BuiltinClasses().at("tire") : plan.objects[0].extent;
    EXPECT_EQ(o.extent, o_extent) << f.index;
    EXPECT_NEAR(o.position.z() - 0.5 * o.extent.z(), 0, 1e-9) << f.index;
    EXPECT_EQ(b.extent, f.index >= 3 ? BuiltinClasses().at("sphere") : plan.objects[1].extent);
    EXPECT_EQ(b.asset, f.index >= 3 ? "sphere" : "cube");
    EXPECT_EQ(b.class_id, 9u);  // a labelled target keeps its label
  }
  // Rendered: the class id layer shows the new class, and the gate passes.
  testing::TempDir dir;
  const auto collection = testing::GenerateValidated(dir, scene, capture);
  ASSERT_EQ(collection["frames"].size(), 4u);
  for (int k = 0; k < 4; ++k) {
    for (const auto& object : collection["frames"][k]["objects"]) {
      if (object["name"] != "O#1") continue;
      EXPECT_EQ(object["asset"], k >= 2 ? "tire" : "barrel");
      EXPECT_EQ(object["class_id"].get<uint32_t>(), k >= 2 ? ids["debris"] : ids["barrel"]);
      char stem[16];
      std::snprintf(stem, sizeof(stem), "%06d.exr", k);
      const exr::FlatImage classes = exr::ReadFlatExr(dir / "out" / "classid" / stem, {"id"});
      int64_t pixels = 0;
      for (uint32_t id : classes.Get("id").uints)
        pixels += id == object["class_id"].get<uint32_t>();
      EXPECT_EQ(pixels, object["visible_pixels"].get<int64_t>()) << k;
      EXPECT_GT(pixels, 0);
    }
  }
}

const char* kClutter =
    "LSCENE = ONE(W) MANY(O, 6) ONE(Z)\n"
    "W = terrain{size:[80,80],height:{perlin:{amplitude:1.5}}}\n"
    "O = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-10,-10,"
    "-99],[10,10,99]]}}\n"
    "Z = object{class:sphere,extent:[3,3,3],position:{ON:W,within:[[-3,-3,-99],"
    "[3,3,99]]}}\n";
const char* kRescatter =
    "LCAP = ONE(P) ONE(CL)\n"
    "P = path{waypoints:[[0,0,40],[0,0,40],[0,0,40],[0,0,40],[0,0,40],[0,0,"
    "40]]}\n"
    "CL = collection{CO:{move:[P]},O:{during:P,rescatter:true}}\n";

TEST(Rescatter, EveryFrameDrawsNewPlacesThatKeepTheConstraints) {
  const Plan plan = PlanText(kClutter, kRescatter, 5);
  ASSERT_EQ(plan.frames.size(), 6u);
  std::set<double> xs;
  for (const PlannedFrame& f : plan.frames) {
    const gen::WorldState world = gen::WorldAt(plan, f);
    for (size_t i = 0; i < world.objects.size(); ++i) {
      const gen::ObjectState& o = world.objects[i];
      if (o.planned->symbol != "O") continue;
      xs.insert(o.position.x());
      // within the box, on the ground
      EXPECT_GE(o.position.x() - 1, -10 - 1e-9);
      EXPECT_LE(o.position.x() + 1, 10 + 1e-9);
      EXPECT_GE(o.position.y() - 1, -10 - 1e-9);
      EXPECT_LE(o.position.y() + 1, 10 + 1e-9);
      EXPECT_NEAR(
          o.position.z() - 1, TerrainHeight(plan.terrain, o.position.x(), o.position.y()), 1e-9);
      // overlap:false (the default) still holds, against everything
      for (size_t j = 0; j < world.objects.size(); ++j)
        if (j != i && world.objects[j].visible && o.visible) {
          EXPECT_FALSE(o.Box().Intersects(world.objects[j].Box()))
              << o.planned->name << " and " << world.objects[j].planned->name << " frame "
              << f.index;
        }
    }
  }
  EXPECT_EQ(xs.size(), 6u * 6u) << "every copy moves on every frame";
  // Frame k's draw depends on (seed, k) only: any frame range is the same.
  for (int64_t b = 0; b < 6; ++b) {
    const Plan part = PlanText(kClutter, kRescatter, 5, FrameRange{b, b + 1});
    ASSERT_EQ(part.frames.size(), 1u);
    EXPECT_EQ(PlannedFrameToJson(part.frames[0]), PlannedFrameToJson(plan.frames[b]));
  }
  // Another seed, other places.
  EXPECT_NE(PlannedFrameToJson(PlanText(kClutter, kRescatter, 6).frames[2]),
            PlannedFrameToJson(plan.frames[2]));
}

TEST(Rescatter, TheOverlapPolicyHoldsWhenTheSpaceIsFull) {
  // Four 2 m cubes in a 4.2 m square rarely all find a free place: with
  // on_overlap:hide the ones that cannot are hidden on that frame.
  const std::string tight =
      "LSCENE = ONE(W) MANY(O, 4)\nW = terrain{size:[40,40]}\n"
      "O = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-2.1,-2.1,"
      "-9],[2.1,2.1,9]]},on_overlap:hide,retries:3}\n";
  const Plan plan = PlanText(tight, kRescatter, 2);
  int hidden = 0;
  for (const PlannedFrame& f : plan.frames) {
    const gen::WorldState world = gen::WorldAt(plan, f);
    for (size_t i = 0; i < world.objects.size(); ++i) {
      if (!world.objects[i].visible) {
        ++hidden;
        continue;
      }
      for (size_t j = i + 1; j < world.objects.size(); ++j)
        if (world.objects[j].visible) {
          EXPECT_FALSE(world.objects[i].Box().Intersects(world.objects[j].Box()));
        }
    }
  }
  EXPECT_GT(hidden, 0);
  // on_overlap:allow keeps the overlapping draws.
  const std::string strict =
      "LSCENE = ONE(W) MANY(O, 4)\nW = terrain{size:[40,40]}\n"
      "O = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-2.1,-2.1,"
      "-9],[2.1,2.1,9]]},on_overlap:allow,retries:3}\n";
  EXPECT_NO_THROW(PlanText(strict, kRescatter, 2));  // allow: overlaps kept
}

// Moving objects, class swaps and re-scatters in one capture: `--frames` and
// `--shard` give byte-identical frames (layers and truth) to a single run.
TEST(ObjectsOverTime, FrameRangesAndShardsEqualTheSingleRun) {
  testing::TempDir dir;
  std::ofstream(dir / "s.lscene")
      << "LSCENE = ONE(W) ONE(CAR) MANY(O, 5)\n"
         "W = terrain{size:[100,100],height:{perlin:{amplitude:1}}}\n"
         "CAR = object{class:cube,extent:[2,1,1],position:{ON:W,within:[[-1,"
         "-8.5,-10],[1,-7.5,10]]}}\n"
         "O = object{class:{rock:0.5,barrel:0.5},position:{ON:W,within:[[-6,-4,"
         "-99],[6,6,99]]}}\n";
  std::ofstream(dir / "c.lcap")
      << "LCAP = ONE(CO) ONE(P) ONE(DRIVE) ONE(CL)\n"
         "CO = camera{csettings:{res:[64,48],fps:10},targets:[CAR,O]}\n"
         "P = path{waypoints:{points:[[0,-3,25],[2,-3,25]],speed:5}}\n"
         "DRIVE = path{waypoints:{points:[[-6,-8,0],[6,-8,0]],speed:4,"
         "interpolation:spline}}\n"
         "CL = collection{CO:{move:[P]},CAR:{move:[DRIVE],heading:true},"
         "O:{during:P,rescatter:true},{after:1,class:{tire:0.5,cone:0.5}}}\n";
  const std::string inputs = (dir / "s.lscene").string() + " " + (dir / "c.lcap").string();
  auto generate = [&](const std::string& name, const std::string& flags) {
    const auto result =
        testing::RunCommandLine(testing::LsdsBinary() + " generate " + inputs + " -o " +
                                (dir / name).string() + " --spp 1 -q " + flags);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    std::ifstream in(dir / name / "collection.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json single = generate("single", "");
  ASSERT_EQ(single["frames"].size(), 5u);
  const auto validated = testing::RunCommandLine(testing::LsdsBinary() + " validate " +
                                                 (dir / "single").string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  for (const auto& [name, flags] : std::vector<std::pair<std::string, std::string>>{
           {"range", "--frames 2:4"}, {"shard", "--shard 1/2"}}) {
    const nlohmann::json part = generate(name, flags);
    ASSERT_FALSE(part["frames"].empty()) << name;
    for (const auto& frame : part["frames"]) {
      const int64_t k = frame["index"];
      EXPECT_EQ(frame, single["frames"][k]) << name << " frame " << k;
      for (const auto& [layer, file] : frame["files"].items())
        EXPECT_TRUE(ReadFile(dir / name / file.get<std::string>()) ==
                    ReadFile(dir / "single" / file.get<std::string>()))
            << name << " " << file;
    }
  }
}

}  // namespace
}  // namespace lsds
