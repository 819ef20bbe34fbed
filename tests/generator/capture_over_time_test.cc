// LCAP over time (docs/languages.md): scene changes of the environment, the
// sun by date and time at a geo-referenced place, the survey metadata a UAV
// logs (GSD, footprint, latitude/longitude), checked on plans and renders.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "generator/generate.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "generator/plan/terrain_height.h"
#include "generator/plan_source.h"
#include "generator/scene/terrain.h"
#include "generator/scene/world.h"
#include "generator/survey.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/solar_position.h"
#include "tests/generator/generate_validated.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

using testing::PlanText;

TEST(CaptureOverTime, EnvironmentChangesApplyFromTheirFrame) {
  const Plan plan = PlanText(
      "LSCENE = ONE(S) ONE(DL) ONE(A) ONE(W)\nS = skybox{color:blue}\n"
      "DL = light{elevation:40,azimuth:90}\nA = atmosphere{visibility:5000}\n"
      "W = terrain{size:[100,100],material:grassy}\n",
      "LCAP = ONE(P) ONE(CL)\nP = path{waypoints:[[0,0,30],[1,0,30]]}\n"
      "CL = collection{CO:{move:[P:3]},A:{after:P:1,visibility:500},"
      "DL:{during:P:3,azimuth:[200,300]},S:{after:P:2,clouds:{type:stratus,"
      "density:0.8}},W:{after:P:2,material:sandy}}\n");
  ASSERT_EQ(plan.frames.size(), 6u);
  for (const PlannedFrame& f : plan.frames) {
    const PlannedEnvironment e = EnvironmentAt(plan, f);
    EXPECT_NEAR(e.fog_density, f.index >= 2 ? 3.912 / 500 : 3.912 / 5000, 1e-12);
    if (f.index >= 4) {
      EXPECT_GE(e.sun.azimuth_deg, 200);
      EXPECT_LE(e.sun.azimuth_deg, 300);
      EXPECT_EQ(e.sky.cloud_type, "stratus");
      EXPECT_EQ(e.terrain_material, "sandy");
    } else {
      EXPECT_EQ(e.sun.azimuth_deg, 90);
      EXPECT_EQ(e.terrain_material, "grassy");
    }
  }
  // `during` draws anew on every frame.
  EXPECT_NE(EnvironmentAt(plan, plan.frames[4]).sun.azimuth_deg,
            EnvironmentAt(plan, plan.frames[5]).sun.azimuth_deg);
  // An unknown key of the changed symbol is a located error.
  try {
    PlanText("LSCENE = ONE(DL)\nDL = light{elevation:40}\n",
             "LCAP = ONE(P) ONE(CL)\nP = path{waypoints:[[0,0,30]]}\n"
             "CL = collection{CO:{move:[P]},DL:{azimut:10}}\n");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 3);
    EXPECT_NE(e.message().find("azimuth"), std::string::npos) << e.message();
  }
}

TEST(CaptureOverTime, TimingsReferToFramesCollectionsAndTable3Spellings) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(O)\nW = terrain{size:[50,50]}\n"
      "O = object{class:cube,position:{ON:W}}\n";
  // Table 3's words: `scene change`, `create path`, `increment point`; two
  // collections flown in order; changes after frame 1, during frame 4 and
  // after the first collection.
  const Plan plan =
      PlanText(scene,
               "LCAP = ONE(P) ONE(Q) ONE(SCS1) ONE(CL1) ONE(CL2)\n"
               "P = create path{waypoints:[[0,0,30],[1,0,30],[2,0,30]]}\n"
               "Q = path{increment point:{start:[0,0,30],step:[1,1,0],count:[2,1,1]}}\n"
               "SCS1 = scene change{O:{material:gold}}\n"
               "CL1 = collection{CO:{move:[P]},O:{after:1,visible:false},{during:4,"
               "material:rust}}\n"
               "CL2 = collection{CO:{move:[Q]},SCS1:{after:CL1}}\n");
  ASSERT_EQ(plan.frames.size(), 5u);
  auto has = [&](int k, auto pred) {
    for (const ObjectChange& c : plan.frames[k].changes)
      if (pred(c)) return true;
    return false;
  };
  auto hidden = [](const ObjectChange& c) { return c.visible.has_value(); };
  auto gold = [](const ObjectChange& c) { return c.material && *c.material == "gold"; };
  auto rust = [](const ObjectChange& c) { return c.material && *c.material == "rust"; };
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(has(k, hidden), k >= 2) << k;  // after frame 1
    EXPECT_EQ(has(k, rust), k == 4) << k;    // during frame 4 only
    EXPECT_EQ(has(k, gold), k >= 3) << k;    // after CL1's three frames
  }
  EXPECT_EQ(plan.frames[3].sequence, "Q(1)");
}

TEST(CaptureOverTime, ASmoothFlightAdvancesSpeedOverFpsPerFrame) {
  const std::string scene = "LSCENE = ONE(W)\nW = terrain{size:[300,300]}\n";
  // 10 m/s at 10 fps: 1 m per frame along a 30 m + 40 m dog-leg.
  const Plan plan = PlanText(scene,
                             "LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{fps:10}}\n"
                             "P = "
                             "path{waypoints:{points:[[0,0,40],[30,0,40],[30,40,40]],speed:10}}\n");
  ASSERT_EQ(plan.frames.size(), 71u);
  for (size_t k = 1; k < plan.frames.size(); ++k) {
    const Eigen::Vector3d a = CameraCenterInWorld(plan.frames[k - 1].cam_from_world);
    const Eigen::Vector3d b = CameraCenterInWorld(plan.frames[k].cam_from_world);
    // Along the path 1 m per frame; the corner cuts the chord below 1 m.
    EXPECT_LE((b - a).norm(), 1.0 + 1e-9);
    if (k != 30) {
      EXPECT_NEAR((b - a).norm(), 1.0, 1e-9) << k;
    }
    EXPECT_NEAR(plan.frames[k].time - plan.frames[k - 1].time, 0.1, 1e-12);
    ASSERT_TRUE(plan.frames[k].camera_velocity.has_value());
    EXPECT_NEAR(plan.frames[k].camera_velocity->norm(), 10.0, 1e-9);
    EXPECT_EQ(plan.frames[k].shot, 0);  // one continuous shot
  }
  EXPECT_TRUE(plan.frames[10].camera_velocity->isApprox(Eigen::Vector3d(10, 0, 0)));
  EXPECT_TRUE(plan.frames[50].camera_velocity->isApprox(Eigen::Vector3d(0, 10, 0)));
  EXPECT_TRUE(
      CameraCenterInWorld(plan.frames[70].cam_from_world).isApprox(Eigen::Vector3d(30, 40, 40)));
  // A spline passes through its waypoints and is smooth: no corner.
  const Plan smooth =
      PlanText(scene,
               "LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{fps:10}}\n"
               "P = path{waypoints:{points:[[0,0,40],[30,0,40],[30,40,40]],speed:10,"
               "interpolation:spline}}\n");
  double worst_turn = 0;
  for (size_t k = 1; k < smooth.frames.size(); ++k) {
    const Eigen::Vector3d a = *smooth.frames[k - 1].camera_velocity,
                          b = *smooth.frames[k].camera_velocity;
    worst_turn =
        std::max(worst_turn, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
  }
  EXPECT_LT(worst_turn * 180 / M_PI, 15);  // the linear path turns 90 at once
}

TEST(CaptureOverTime, ASmoothFlightPassesTheGateWithValidMotion) {
  testing::TempDir dir;
  const auto collection = testing::GenerateValidated(
      dir,
      "LSCENE = ONE(W) MANY(O, 6)\n"
      "W = terrain{size:[120,120],height:{perlin:{amplitude:2}}}\n"
      "O = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-15,-15,-100],[15,15,100]]}}\n",
      "LCAP = ONE(CO) ONE(P)\n"
      "CO = camera{csettings:{res:[160,120],fps:5},targets:[O]}\n"
      "P = path{waypoints:{points:[[-20,-20,25],[0,0,30],[20,-10,25]],"
      "speed:8,interpolation:spline}}\n");
  EXPECT_GT(collection["frames"].size(), 8u);
  EXPECT_TRUE(collection["frames"][3].contains("camera_velocity"));
}

TEST(CaptureOverTime, TheSceneRecordNamesTheTerrainMaterialOfEveryFrame) {
  testing::TempDir dir;
  const auto collection = testing::GenerateValidated(
      dir,
      "LSCENE = ONE(W)\nW = terrain{size:[60,60],material:sandy}\n",
      "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
      "CO = camera{csettings:{res:[64,48]}}\n"
      "P = path{waypoints:[[0,0,30],[0,0,30],[0,0,30]]}\n"
      "CL = collection{CO:{move:[P]},W:{after:0,material:grass}}\n");  // the paper's word
  const auto& frames = collection["frames"];
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0]["scene"]["terrain_material"], "sandy");
  EXPECT_EQ(frames[1]["scene"]["terrain_material"], "grass");  // after frame 0
  EXPECT_EQ(frames[2]["scene"]["terrain_material"], "grass");
}

// A flat terrain for the first flight of P, hills from its second (a shot's first frame), lower
// hills of the same frequency from its third (the renderer's third world re-meshes a recycled
// scene's ground): four cubes ON the terrain.
const char* kGroundScene =
    "LSCENE = ONE(W) MANY(O, 4)\n"
    "W = terrain{size:[80,80]}\n"
    "O = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-12,-12,-100],[12,12,100]]}}\n";
const char* kGroundCapture =
    "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
    "CO = camera{csettings:{res:[96,72]},targets:[O]}\n"
    "P = path{waypoints:[[0,0,40],[1,0,40],[2,0,40]]}\n"
    "CL = collection{CO:{move:[P:3]},W:[{after:P:1,height:{perlin:{amplitude:3,frequency:0.04}}},"
    "{after:P:2,perlin:1.5}]}\n";

// The terrain amplitude of frame `k` of kGroundCapture.
double GroundAmplitude(int64_t k) { return k >= 6 ? 1.5 : k >= 3 ? 3.0 : 0.0; }

TEST(CaptureOverTime, ATerrainShapeChangeAtAShotReseatsWhatStandsOnIt) {
  const Plan plan = PlanText(kGroundScene, kGroundCapture, 0);
  ASSERT_EQ(plan.frames.size(), 9u);
  EXPECT_EQ(plan.frames[2].shot, 0);
  EXPECT_EQ(plan.frames[3].shot, 3);  // P(2) is a shot of its own
  EXPECT_EQ(plan.frames[6].shot, 6);
  double largest_base = 0;
  for (const PlannedFrame& f : plan.frames) {
    const PlannedTerrain ground = TerrainAt(plan, f);
    EXPECT_EQ(ground.perlin_amplitude, GroundAmplitude(f.index)) << f.index;
    EXPECT_EQ(ground.perlin_frequency, f.index >= 3 ? 0.04 : 0.05) << f.index;
    const gen::WorldState world = gen::WorldAt(plan, f);
    ASSERT_EQ(world.objects.size(), 4u);
    for (const gen::ObjectState& o : world.objects) {
      const double half_z = (o.world_from_object.cwiseAbs() * (0.5 * o.extent)).z();
      const double base = o.position.z() - half_z;
      // The box's base on the ground under its centre, on every frame of each shot.
      EXPECT_NEAR(base, TerrainHeight(ground, o.position.x(), o.position.y()), 1e-9)
          << "frame " << f.index << " " << o.planned->name;
      largest_base = std::max(largest_base, std::abs(base));
    }
  }
  EXPECT_GT(largest_base, 0.1);  // the hills did move the cubes
  // The plan's JSON carries the change, and reads back to the same ground.
  const Plan back = PlanFromJson(PlanToJson(plan), "plan.json");
  EXPECT_EQ(PlanToJson(back), PlanToJson(plan));
  EXPECT_EQ(TerrainAt(back, back.frames[4]).perlin_amplitude, 3.0);
  EXPECT_EQ(TerrainAt(back, back.frames[7]).perlin_amplitude, 1.5);
  EXPECT_EQ(TerrainAt(back, back.frames[7]).perlin_frequency, 0.04);
  EXPECT_EQ(TerrainAt(back, back.frames[1]).perlin_amplitude, 0.0);
  // A change that would take effect inside a shot is a located error showing the accepted form.
  const std::string error =
      testing::PlanErrorOf(kGroundScene,
                           "LCAP = ONE(CO) ONE(P) ONE(CL)\nCO = camera{csettings:{res:[96,72]}}\n"
                           "P = path{waypoints:[[0,0,40],[1,0,40],[2,0,40]]}\n"
                           "CL = collection{CO:{move:[P:2]},W:{after:1,height:{perlin:2}}}\n");
  EXPECT_NE(error.find("c.lcap:4:"), std::string::npos) << error;
  EXPECT_NE(error.find("a terrain shape change takes effect only where a shot starts"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("starts at frame 2, inside the shot of P(1) that starts at frame 0"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("W:{during:P:1, height:{...}}"), std::string::npos) << error;
}

// The height at (x, y) of the rendered terrain mesh (gen::MakeTerrainMesh): its grid of
// TerrainHeight vertices, each cell cut along its diagonal into triangles (a, b, d), (a, d, c).
double TerrainMeshHeight(const PlannedTerrain& terrain, double x, double y) {
  const Eigen::Vector2i grid = gen::TerrainGrid(terrain);
  const double sx = terrain.size.x(), sy = terrain.size.y();
  const double gx = (x + sx / 2) / sx * grid.x(), gy = (y + sy / 2) / sy * grid.y();
  const int i = std::clamp(static_cast<int>(std::floor(gx)), 0, grid.x() - 1);
  const int j = std::clamp(static_cast<int>(std::floor(gy)), 0, grid.y() - 1);
  auto vertex = [&](int vi, int vj) {
    const double vx = -sx / 2 + sx * vi / grid.x(), vy = -sy / 2 + sy * vj / grid.y();
    return static_cast<double>(static_cast<float>(TerrainHeight(terrain, vx, vy)));
  };
  const double za = vertex(i, j), zb = vertex(i + 1, j), zc = vertex(i, j + 1),
               zd = vertex(i + 1, j + 1);
  const double u = gx - i, v = gy - j;
  return u >= v ? za + u * (zb - za) + v * (zd - zb) : za + v * (zc - za) + u * (zd - zc);
}

TEST(CaptureOverTime, TheRenderedGroundAndBoxesFollowATerrainShapeChange) {
  testing::TempDir dir;
  const auto collection = testing::GenerateValidated(dir, kGroundScene, kGroundCapture);
  const Plan plan = PlanText(kGroundScene, kGroundCapture, 0);  // lsds generate's seed
  const CollectionReader reader(dir / "out");
  int frames = 0;
  reader.ForEachFrame([&](const Frame& f) {
    ++frames;
    const PlannedTerrain ground = TerrainAt(plan, plan.frames[static_cast<size_t>(f.index)]);
    EXPECT_EQ(f.scene["terrain_shape"]["perlin_amplitude"], GroundAmplitude(f.index));
    EXPECT_EQ(f.scene["terrain_shape"]["perlin_frequency"], f.index >= 3 ? 0.04 : 0.05);
    int boxes = 0;
    for (const ObjectTruth& o : f.objects) {
      ASSERT_TRUE(o.obb.has_value()) << o.name;
      const OrientedBox& obb = *o.obb;
      const Eigen::Vector3d half = obb.world_from_box.cwiseAbs() * obb.half_extents;
      EXPECT_NEAR(
          obb.center.z() - half.z(), TerrainHeight(ground, obb.center.x(), obb.center.y()), 1e-9)
          << "frame " << f.index << " " << o.name;
      ++boxes;
    }
    EXPECT_EQ(boxes, 4) << f.index;
    // Every ground pixel's world position lies on this shot's terrain mesh, and off the other
    // shot's ground.
    const exr::FlatImage position = reader.ReadFlatLayer(f, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage ids = reader.ReadFlatLayer(f, "instanceid", {"id"});
    double worst = 0, off_flat = 0;
    int ground_pixels = 0;
    for (size_t p = 0; p < ids.Get("id").uints.size(); ++p) {
      if (ids.Get("id").uints[p] != plan.terrain.instance_id) continue;
      const double x = position.Get("X").floats[p], y = position.Get("Y").floats[p],
                   z = position.Get("Z").floats[p];
      worst = std::max(worst, std::abs(z - TerrainMeshHeight(ground, x, y)));
      off_flat = std::max(off_flat, std::abs(z));
      ++ground_pixels;
    }
    EXPECT_GT(ground_pixels, 1000) << f.index;
    EXPECT_LT(worst, 1e-3) << f.index;
    if (f.index >= 3) {
      EXPECT_GT(off_flat, 0.5) << f.index;
    }
  });
  EXPECT_EQ(frames, 9);
  EXPECT_EQ(collection["frames"].size(), 9u);
}

const char* kSunScene =
    "LSCENE = ONE(G) ONE(DL) ONE(W) ONE(POLE)\n"
    "G = georeference{latitude:47.3769,longitude:8.5417,altitude:408}\n"
    "DL = light{date:\"2026-06-21\",time:\"08:00\",utc_offset:2}\n"
    "W = terrain{size:[200,200]}\n"
    "POLE = object{class:cube,extent:[1,1,12],position:{ON:W,within:[[-0.5,"
    "-0.5,-100],[0.5,0.5,100]]}}\n";

TEST(CaptureOverTime, TheSunFollowsTheClockOfEveryFrame) {
  // One frame an hour (fps 1/3600) from 08:00 local.
  const Plan plan =
      PlanText(kSunScene,
               "LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{fps:0.000277777777778}}\n"
               "P = path{waypoints:[[0,0,60],[0,0,60],[0,0,60],[0,0,60],[0,0,60]]}\n");
  ASSERT_TRUE(plan.geo.has_value());
  for (const PlannedFrame& f : plan.frames) {
    const SolarPosition expected =
        SunPositionAt(UnixSeconds(2026, 6, 21, 8, 0, 0, 2) + f.time, 47.3769, 8.5417);
    const PlannedEnvironment e = EnvironmentAt(plan, f);
    EXPECT_NEAR(e.sun.azimuth_deg, expected.azimuth_deg, 1e-9) << f.index;
    EXPECT_NEAR(e.sun.elevation_deg, expected.elevation_deg, 1e-9);
  }
  // A morning in June: the sun climbs and swings south.
  EXPECT_GT(EnvironmentAt(plan, plan.frames[4]).sun.azimuth_deg,
            EnvironmentAt(plan, plan.frames[0]).sun.azimuth_deg + 30);
  // A date without a place is a located error.
  try {
    PlanText("LSCENE = ONE(DL)\nDL = light{date:\"2026-06-21\",time:\"8:00\"}\n",
             "LCAP = ONE(P)\nP = path{waypoints:[[0,0,30]]}\n");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("georeference"), std::string::npos);
    EXPECT_EQ(e.location().line, 2);
  }
}

// A time-of-day interval (the paper's LCAP "interval of ... times of day"): drawn per frame under
// `during`, every local time within it.
TEST(CaptureOverTime, ATimeOfDayIntervalIsDrawnWithinItsBounds) {
  const Plan plan =
      PlanText(kSunScene,
               "LCAP = ONE(CO) ONE(P) ONE(CL)\nCO = camera{}\n"
               "P = path{waypoints:[[0,0,60],[0,0,60],[0,0,60],[0,0,60],[0,0,60],[0,0,60],"
               "[0,0,60],[0,0,60],[0,0,60],[0,0,60]]}\n"
               "CL = collection{CO:{move:[P]},DL:{during:P,time:[\"08:00\",\"17:00\"]}}\n");
  double earliest = 24, latest = 0;
  for (const PlannedFrame& f : plan.frames) {
    const PlannedEnvironment e = EnvironmentAt(plan, f);
    ASSERT_TRUE(e.sun.clock_utc_s);
    const double local = *e.sun.clock_utc_s - UnixSeconds(2026, 6, 21, 0, 0, 0, e.sun.utc_offset_h);
    EXPECT_GE(local / 3600, 8) << f.index;
    EXPECT_LE(local / 3600, 17) << f.index;
    earliest = std::min(earliest, local / 3600);
    latest = std::max(latest, local / 3600);
  }
  EXPECT_GT(latest - earliest, 3);  // ten uniform draws over 9 hours
  const std::string error =
      testing::PlanErrorOf(kSunScene,
                           "LCAP = ONE(P) ONE(CL)\nP = path{waypoints:[[0,0,60]]}\n"
                           "CL = collection{DL:{time:[\"17:00\",\"08:00\"]}}\n");
  EXPECT_NE(error.find("c.lcap:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("a time interval runs forward in one day"), std::string::npos) << error;
}

// The direction (xy) from the pole's foot to the centroid of its shadow.
Eigen::Vector2d ShadowDirection(const std::filesystem::path& root, int frame) {
  char stem[16];
  std::snprintf(stem, sizeof(stem), "%06d.exr", frame);
  const exr::FlatImage shadow = exr::ReadFlatExr(root / "shadow" / stem, {"Y"});
  // World position through the collection reader: either storage layout.
  const CollectionReader reader(root);
  exr::FlatImage position;
  reader.ForEachFrame([&](const Frame& f) {
    if (f.index == frame) position = reader.ReadFlatLayer(f, "worldposition", {"X", "Y", "Z"});
  });
  Eigen::Vector2d sum(0, 0);
  int n = 0;
  for (size_t p = 0; p < shadow.Get("Y").floats.size(); ++p) {
    const float z = position.Get("Z").floats[p];
    if (shadow.Get("Y").floats[p] > 0.5f || !(std::abs(z) < 0.01)) continue;
    sum += Eigen::Vector2d(position.Get("X").floats[p], position.Get("Y").floats[p]);
    ++n;
  }
  EXPECT_GT(n, 20) << "frame " << frame;
  return (sum / std::max(n, 1)).normalized();
}

TEST(CaptureOverTime, ShadowsTurnWithTheSunOverAnOrbit) {
  testing::TempDir dir;
  std::ofstream(dir / "s.lscene") << kSunScene;
  // An orbit of 4 views, one every 2 hours from 08:00.
  std::ofstream(dir / "c.lcap")
      << "LCAP = ONE(CO) ONE(P)\n"
         "CO = camera{csettings:{fov:70,res:[160,120],fps:0.000138888888889}}\n"
         "P = path{create hemi:{cam radius:[45,45,1],obj angle:[0,360,4],"
         "cam angle:[70,70,1],center:[0,0,0]}}\n";
  const Plan plan = gen::PlanFromScene((dir / "s.lscene").string(), (dir / "c.lcap").string(), 1);
  gen::GenerateOptions options;
  options.output = dir / "out";
  options.spp = 1;
  options.progress = false;
  gen::GenerateCollection(plan, options);
  std::ifstream in(dir / "out" / "collection.json");
  const auto collection = nlohmann::json::parse(in);
  double previous_angle = 0;
  for (int k = 0; k < 4; ++k) {
    const auto& sun = collection["frames"][k]["scene"]["sun"];
    const Eigen::Vector2d away_from_sun(-sun["direction"][0].get<double>(),
                                        -sun["direction"][1].get<double>());
    const Eigen::Vector2d shadow = ShadowDirection(dir / "out", k);
    const double angle = std::acos(std::clamp(shadow.dot(away_from_sun.normalized()), -1.0, 1.0));
    EXPECT_LT(angle * 180 / M_PI, 10) << "frame " << k;
    const double heading = std::atan2(shadow.y(), shadow.x());
    if (k > 0) {
      EXPECT_GT(std::abs(heading - previous_angle) * 180 / M_PI, 15)
          << "the shadow did not turn between frames " << k - 1 << " and " << k;
    }
    previous_angle = heading;
  }
}

TEST(CaptureOverTime, NadirSurveyMetadataIsAnalytic) {
  const Plan plan = PlanText(
      "LSCENE = ONE(G) ONE(W)\n"
      "G = georeference{latitude:47.3769,longitude:8.5417,altitude:408}\n"
      "W = terrain{size:[400,400]}\n",
      "LCAP = ONE(CO) ONE(P)\n"
      "CO = camera{csettings:{fov:60,res:[400,300]}}\n"
      "P = path{waypoints:[[10,20,50]]}\n");
  MetadataFrame metadata;
  gen::AddSurveyMetadata(plan, plan.frames[0], &metadata);
  const PinholeCamera& camera = plan.frames[0].camera;
  ASSERT_TRUE(metadata.gsd_m && metadata.altitude_agl_m && metadata.geo);
  EXPECT_NEAR(*metadata.altitude_agl_m, 50, 1e-9);
  EXPECT_NEAR(*metadata.gsd_m, 50 / camera.fx, 1e-12);
  ASSERT_EQ(metadata.footprint.size(), 4u);
  // A nadir camera, image top to the north: the ground rectangle is
  // (w / fx) x (h / fy) times the altitude, centred under the camera.
  const double half_x = 0.5 * camera.width / camera.fx * 50,
               half_y = 0.5 * camera.height / camera.fy * 50;
  const Eigen::Vector2d expected[4] = {{10 - half_x, 20 + half_y},
                                       {10 + half_x, 20 + half_y},
                                       {10 + half_x, 20 - half_y},
                                       {10 - half_x, 20 - half_y}};
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(metadata.footprint[c].x(), expected[c].x(), 1e-9) << c;
    EXPECT_NEAR(metadata.footprint[c].y(), expected[c].y(), 1e-9) << c;
    EXPECT_NEAR(metadata.footprint[c].z(), 0, 1e-9);
  }
  EXPECT_NEAR(metadata.geo->altitude_msl_m, 458, 0.01);
  EXPECT_GT(metadata.geo->latitude_deg, 47.3769);
  EXPECT_GT(metadata.geo->longitude_deg, 8.5417);
}

}  // namespace
}  // namespace lsds
