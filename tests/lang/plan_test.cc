// Property tests of the planner over many seeds (docs/languages.md, "Determinism"),
// determinism and frame subsets, the plan's JSON form.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>

#include "generator/lang/planner.h"
#include "generator/lang/scene/placed_objects.h"
#include "generator/plan/plan_json.h"
#include "generator/plan/terrain_height.h"
#include "generator/scene/world.h"
#include "libs/collection/schema.h"
#include "libs/geometry/oriented_box.h"
#include "tests/build_paths.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

const std::string kExamples = ::lsds::testing::ExamplesDir();

using testing::PlanText;

Eigen::Vector3d HalfAabb(const PlannedObject& o) {
  return o.world_from_object.cwiseAbs() * (0.5 * o.extent);
}

const PlannedObject* Find(const Plan& plan, const std::string& name) {
  for (const PlannedObject& o : plan.objects)
    if (o.name == name) return &o;
  return nullptr;
}

TEST(LangPlan, OnPutsTheBaseOnTheTerrainSurface) {
  const std::string scene =
      "LSCENE = ONE(W) MANY(R, 30) ONE(BOX) MANY(TOP, 3)\n"
      "W = terrain{size:[80,80],height:{perlin:{amplitude:4,frequency:0.05}}}\n"
      "R = "
      "object{class:{rock:0.5,barrel:0.5},rotation:[[0,0,0],[40,40,360]],scale:"
      "[0.5,2],position:{ON:W}}\n"
      "BOX = object{class:cube,extent:[6,6,2],position:{ON:W}}\n"
      "TOP = object{class:jerrycan,position:{ON:BOX}}\n";
  for (uint64_t seed = 0; seed < 40; ++seed) {
    const Plan plan = PlanText(scene, "", seed);
    const PlannedObject* box = Find(plan, "BOX#1");
    ASSERT_NE(box, nullptr);
    for (const PlannedObject& o : plan.objects) {
      const double base = o.position.z() - HalfAabb(o).z();
      if (o.symbol == "TOP") {
        EXPECT_NEAR(base, box->position.z() + HalfAabb(*box).z(), 1e-9)
            << o.name << " seed " << seed;
        EXPECT_LE(std::abs(o.position.x() - box->position.x()), 3 + 1e-9);
      } else {
        EXPECT_NEAR(base, TerrainHeight(plan.terrain, o.position.x(), o.position.y()), 1e-9)
            << o.name << " seed " << seed;
        EXPECT_LE(std::abs(o.position.x()) + HalfAabb(o).x(), 40 + 1e-9);
        EXPECT_LE(std::abs(o.position.y()) + HalfAabb(o).y(), 40 + 1e-9);
      }
    }
  }
}

TEST(LangPlan, InAndAroundKeepObjectsInsideTheirBoxes) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(T) ONE(ZONE) MANY(INSIDE, 10) MANY(NEAR, 10) "
      "MANY(ONZONE, 10)\n"
      "W = terrain{size:[100,100],height:{perlin:1}}\n"
      "T = object{class:person,position:{ON:W}}\n"
      "ZONE = "
      "object{class:cube,visible:false,extent:[12,8,6],position:{ON:W,AROUND:{"
      "T:20}}}\n"
      "INSIDE = "
      "object{class:cube,extent:[1,1,1],rotation:[0,0,[0,360]],overlap:true,"
      "position:{IN:ZONE}}\n"
      "NEAR = "
      "object{class:tire,overlap:true,position:{ON:W,AROUND:{T:[3,2,0]}}}\n"
      "ONZONE = object{class:bush,overlap:true,position:{ON:ZONE}}\n";
  for (uint64_t seed = 0; seed < 40; ++seed) {
    const Plan plan = PlanText(scene, "", seed);
    const PlannedObject& t = *Find(plan, "T#1");
    const PlannedObject& zone = *Find(plan, "ZONE#1");
    const Eigen::Vector3d zlo = zone.position - HalfAabb(zone),
                          zhi = zone.position + HalfAabb(zone);
    const Eigen::Vector3d tlo = t.position - HalfAabb(t), thi = t.position + HalfAabb(t);
    EXPECT_LE((zone.position - t.position).head<2>().cwiseAbs().maxCoeff(), 20 + 6 + 0.5);
    for (const PlannedObject& o : plan.objects) {
      const Eigen::Vector3d lo = o.position - HalfAabb(o), hi = o.position + HalfAabb(o);
      if (o.symbol == "INSIDE") {
        // IN an invisible zone: on the terrain inside the zone's footprint (not in its height).
        EXPECT_TRUE((lo.head<2>().array() >= zlo.head<2>().array() - 1e-9).all() &&
                    (hi.head<2>().array() <= zhi.head<2>().array() + 1e-9).all())
            << o.name;
        EXPECT_NEAR(lo.z(), TerrainHeight(plan.terrain, o.position.x(), o.position.y()), 1e-9)
            << o.name;
      } else if (o.symbol == "NEAR") {
        EXPECT_GE(lo.x(), tlo.x() - 3 - 1e-9);
        EXPECT_LE(hi.x(), thi.x() + 3 + 1e-9);
        EXPECT_GE(lo.y(), tlo.y() - 2 - 1e-9);
        EXPECT_LE(hi.y(), thi.y() + 2 + 1e-9);
      } else if (o.symbol == "ONZONE") {
        // ON an invisible zone: stands on the terrain, inside the zone's
        // footprint.
        EXPECT_NEAR(lo.z(), TerrainHeight(plan.terrain, o.position.x(), o.position.y()), 1e-9);
        EXPECT_GE(lo.x(), zlo.x() - 1e-9);
        EXPECT_LE(hi.y(), zhi.y() + 1e-9);
      }
    }
  }
}

TEST(LangPlan, OverlapFalseLeavesNoIntersectingBoxes) {
  const std::string scene =
      "LSCENE = ONE(W) MANY(A, 25) MANY(B, 25)\n"
      "W = terrain{size:[30,30],height:{perlin:0.5}}\n"
      "A = "
      "object{class:{cube:0.5,barrel:0.5},scale:[0.5,2],rotation:[0,0,[0,360]],"
      "position:{ON:W}}\n"
      "B = "
      "object{class:rock,rotation:[[0,0,0],[20,20,360]],overlap:false,on_"
      "overlap:delete,position:{ON:W}}\n";
  for (uint64_t seed = 0; seed < 30; ++seed) {
    const Plan plan = PlanText(scene, "", seed);
    EXPECT_EQ(std::count_if(plan.objects.begin(),
                            plan.objects.end(),
                            [](const PlannedObject& o) { return o.symbol == "A"; }),
              25);
    for (size_t i = 0; i < plan.objects.size(); ++i)
      for (size_t j = i + 1; j < plan.objects.size(); ++j)
        EXPECT_FALSE(ObbOf(plan.objects[i]).Intersects(ObbOf(plan.objects[j])))
            << plan.objects[i].name << " " << plan.objects[j].name << " seed " << seed;
  }
}

// The placement grid (generator/lang/scene/placement_grid.h) across its cases: clutter in cells,
// walls wider than the grid takes, separations larger than a cell.
TEST(LangPlan, OverlapFalseHoldsForWallsAndSeparations) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(WALL) MANY(A, 150) MANY(B, 150)\n"
      "W = terrain{size:[400,400]}\n"
      "WALL = object{class:cube,extent:[380,2,3],position:{ON:W,within:[[-1,-1,-9],[1,1,9]]}}\n"
      "A = object{class:cube,extent:[1,1,1],rotation:[0,0,[0,360]],separation:6,"
      "on_overlap:delete,position:{ON:W,within:[[-60,-60,-9],[60,60,9]]}}\n"
      "B = "
      "object{class:barrel,on_overlap:delete,position:{ON:W,within:[[-60,-60,-9],[60,60,9]]}}\n";
  for (uint64_t seed = 0; seed < 5; ++seed) {
    const Plan plan = PlanText(scene, "", seed);
    ASSERT_GT(plan.objects.size(), 100u);
    for (size_t i = 0; i < plan.objects.size(); ++i)
      for (size_t j = i + 1; j < plan.objects.size(); ++j) {
        // As the planner tests it: the world boxes within the larger separation on every
        // axis and the later object's box, grown by it, meeting the earlier one.
        const PlannedObject& earlier = plan.objects[i];
        const PlannedObject& later = plan.objects[j];
        const double gap = std::max(earlier.separation, later.separation);
        const Eigen::Vector3d apart =
            (later.position - earlier.position).cwiseAbs() - HalfAabb(later) - HalfAabb(earlier);
        OrientedBox grown = ObbOf(later);
        grown.half_extents.array() += gap;
        EXPECT_FALSE((apart.array() < gap).all() && grown.Intersects(ObbOf(earlier)))
            << earlier.name << " " << later.name << " seed " << seed;
      }
  }
}

TEST(LangPlan, DiscreteChoicesConvergeToTheirWeights) {
  const std::string scene =
      "LSCENE = ONE(W) MANY(X, 4000)\n"
      "W = terrain{size:[100,100]}\n"
      "X = "
      "object{class:{cube:0.2,sphere:0.5,cone:0.3},material:{a:1,b:3},overlap:"
      "true,position:{ON:W}}\n";
  const Plan plan = PlanText(scene, "", 11);
  std::map<std::string, int> classes, materials;
  for (const PlannedObject& o : plan.objects) ++classes[o.class_name], ++materials[o.material];
  EXPECT_NEAR(classes["cube"] / 4000.0, 0.2, 0.025);
  EXPECT_NEAR(classes["sphere"] / 4000.0, 0.5, 0.025);
  EXPECT_NEAR(classes["cone"] / 4000.0, 0.3, 0.025);
  EXPECT_NEAR(materials["b"] / 4000.0, 0.75, 0.025);
  // Sky choices across seeds.
  int cumulus = 0;
  for (uint64_t seed = 0; seed < 1000; ++seed)
    cumulus += PlanText(
                   "LSCENE = ONE(S)\nS = "
                   "skybox{clouds:{type:{cumulus:0.3,cirrus:0.7}}}\n",
                   "",
                   seed)
                   .sky.cloud_type == "cumulus";
  EXPECT_NEAR(cumulus / 1000.0, 0.3, 0.05);
}

TEST(LangPlan, HemiPosesLieOnTheSphereLookingAtTheTarget) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(O1)\nW = "
      "terrain{size:[50,50],height:{perlin:1}}\nO1 = "
      "object{class:barrel,position:{ON:W}}\n";
  const std::string capture =
      "LCAP = ONE(CO) ONE(P1) ONE(CL)\nCO = "
      "camera{csettings{fov:30,res:[64,48]},targets:[O1:5]}\n"
      "P1 = path{create hemi:{cam radius:[10,20,3],obj angle:[0,360,4],cam "
      "angle:[30,60,2]}}\n"
      "CL = collection{CO:{move:[P1:2]}}\n";
  for (uint64_t seed = 0; seed < 10; ++seed) {
    const Plan plan = PlanText(scene, capture, seed);
    ASSERT_EQ(plan.frames.size(), 2u * 3 * 4 * 2);
    const Eigen::Vector3d target = plan.objects[0].position;
    const double radii[] = {10, 15, 20}, elevations[] = {30, 60}, azimuths[] = {0, 90, 180, 270};
    for (const PlannedFrame& f : plan.frames) {
      const int i = static_cast<int>(f.index % 24);
      const Eigen::Vector3d eye = CameraCenterInWorld(f.cam_from_world);
      const Eigen::Vector3d d = eye - target;
      EXPECT_NEAR(d.norm(), radii[i / 8], 1e-9);
      EXPECT_NEAR(std::asin(d.z() / d.norm()) * 180 / M_PI, elevations[(i / 4) % 2], 1e-9);
      double az = std::atan2(d.y(), d.x()) * 180 / M_PI;
      if (az < -1e-9) az += 360;
      EXPECT_NEAR(az, azimuths[i % 4], 1e-9);
      const Eigen::Vector3d target_in_cam = f.cam_from_world * target;
      EXPECT_NEAR(target_in_cam.x(), 0, 1e-9);
      EXPECT_NEAR(target_in_cam.y(), 0, 1e-9);
      EXPECT_GT(target_in_cam.z(), 0);
      EXPECT_EQ(f.camera.width, 64);
      EXPECT_NEAR(f.camera.HorizontalFovDeg(), 30, 1e-9);
    }
    EXPECT_EQ(plan.frames[24].sequence, "P1(2)");
  }
}

TEST(LangPlan, GridAndRandomPosesRespectTheirRanges) {
  const Plan plan = MakePlan(kExamples + "/uav_survey.lscene", kExamples + "/uav_survey.lcap", 2);
  ASSERT_EQ(plan.frames.size(), 49u + 2u);
  for (int k = 0; k < 49; ++k) {
    const PlannedFrame& f = plan.frames[k];
    const Eigen::Vector3d c = CameraCenterInWorld(f.cam_from_world);
    const int row = k / 7, col = row % 2 ? 6 - k % 7 : k % 7;  // serpentine
    EXPECT_NEAR(c.x(), -60 + 20 * col, 1.5 + 1e-9);
    EXPECT_NEAR(c.y(), -60 + 20 * row, 1.5 + 1e-9);
    EXPECT_NEAR(c.z() - TerrainHeight(plan.terrain, c.x(), c.y()), 40, 0.5 + 1e-9);
    // Nadir: the optical axis points down.
    const Eigen::Vector3d axis = f.cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(axis.z(), -1, 1e-9);
  }
  // The walker is hidden from the first frame after the grid on.
  EXPECT_TRUE(plan.frames[48].changes.empty());
  ASSERT_EQ(plan.frames[49].changes.size(), 1u);
  EXPECT_EQ(plan.frames[49].changes[0].object, "WALKER#1");
  EXPECT_EQ(*plan.frames[49].changes[0].visible, false);
  // The last waypoint looks at the walker.
  const Eigen::Vector3d walker = Find(plan, "WALKER#1")->position;
  const Eigen::Vector3d w_in_cam = plan.frames[50].cam_from_world * walker;
  EXPECT_NEAR(w_in_cam.head<2>().norm(), 0, 1e-9);

  const Plan random =
      MakePlan(kExamples + "/rocky_sand_clutter.lscene", kExamples + "/rocky_sand_random.lcap", 3);
  ASSERT_EQ(random.frames.size(), 100u);
  for (const PlannedFrame& f : random.frames) {
    const Eigen::Vector3d c = CameraCenterInWorld(f.cam_from_world);
    const double agl = c.z() - TerrainHeight(random.terrain, c.x(), c.y());
    EXPECT_GE(agl, 15 - 1e-9);
    EXPECT_LE(agl, 60 + 1e-9);
    const Eigen::Vector3d axis = f.cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
    EXPECT_LE(std::acos(std::min(1.0, -axis.z())) * 180 / M_PI, 40 + 1e-6);
    // `during:R:2` re-draws the clutter materials on every frame of R(2) only.
    EXPECT_EQ(f.changes.empty(), f.index < 50);
  }
}

// Section 3.2's point blueprint fed to increment point, in the paper's spelling, over hills: a
// uniform grid over the terrain with per-point noise within the blueprint's box, its attitude the
// blueprint's rotation.
TEST(LangPlan, APointBlueprintFedToIncrementPointIsANoisyGridOverTheTerrain) {
  const Plan plan =
      PlanText("LSCENE = ONE(W)\nW = terrain{size:[200,200],height:{perlin:{amplitude:3}}}\n",
               "LCAP = ONE(CO) ONE(N) ONE(P) ONE(CL)\n"
               "CO = camera{csettings:{res:[64,48]}}\n"
               "N = path{create point:{position:[[-2,-2,-1],[2,2,1]],rotation:[0,-70,[0,360]]}}\n"
               "P = create path{increment point:{x:[-40,40,5],y:[-40,40,5],altitude:30,point:N}}\n"
               "CL = collection{CO:{move:[P]}}\n");
  ASSERT_EQ(plan.frames.size(), 25u);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const PlannedFrame& f : plan.frames) {
    const int row = static_cast<int>(f.index / 5), col = row % 2 ? 4 - f.index % 5 : f.index % 5;
    const Eigen::Vector3d c = CameraCenterInWorld(f.cam_from_world);
    // Above the terrain under the perturbed point, as the grid's altitude is.
    const Eigen::Vector3d noise(c.x() - (-40 + 20 * col),
                                c.y() - (-40 + 20 * row),
                                c.z() - TerrainHeight(plan.terrain, c.x(), c.y()) - 30);
    lo = lo.cwiseMin(noise);
    hi = hi.cwiseMax(noise);
    // Pitch -70 (20 degrees off nadir) at every point.
    const Eigen::Vector3d axis = f.cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(std::asin(-axis.z()) * 180 / M_PI, 70, 1e-9) << f.index;
  }
  EXPECT_GE(lo.x(), -2);
  EXPECT_LE(hi.y(), 2);
  EXPECT_GE(lo.z(), -1 - 1e-9);
  EXPECT_LE(hi.z(), 1 + 1e-9);
  EXPECT_GT((hi - lo).minCoeff(), 1);  // noise in x, y and z, not one offset
}

TEST(LangPlan, SameSeedSamePlanAndFrameSubsetsMatch) {
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"paper_example1.lscene", "paper_example1.lcap"},
      {"rocky_sand_clutter.lscene", "rocky_sand_random.lcap"},
      {"uav_survey.lscene", "uav_survey.lcap"}};
  for (const auto& [scene, capture] : inputs) {
    const Plan full = MakePlan(kExamples + "/" + scene, kExamples + "/" + capture, 42);
    const std::string full_text = PlanToJson(full).dump();
    EXPECT_EQ(PlanToJson(MakePlan(kExamples + "/" + scene, kExamples + "/" + capture, 42)).dump(),
              full_text);
    EXPECT_NE(PlanToJson(MakePlan(kExamples + "/" + scene, kExamples + "/" + capture, 43)).dump(),
              full_text);
    const int64_t n = static_cast<int64_t>(full.frames.size());
    for (const auto& [b, e] : std::vector<std::pair<int64_t, int64_t>>{
             {0, 1}, {n / 3, n / 2}, {n - 5, n}, {n - 1, -1}}) {
      const Plan part =
          MakePlan(kExamples + "/" + scene, kExamples + "/" + capture, 42, FrameRange{b, e});
      const int64_t end = e < 0 ? n : e;
      ASSERT_EQ(static_cast<int64_t>(part.frames.size()), end - b) << scene;
      EXPECT_EQ(PlanToJson(part)["objects"], PlanToJson(full)["objects"]);
      for (int64_t k = b; k < end; ++k)
        EXPECT_EQ(PlannedFrameToJson(part.frames[k - b]), PlannedFrameToJson(full.frames[k]))
            << scene << " frame " << k;
    }
  }
}

TEST(LangPlan, PlanJsonMatchesItsSchemaAndRoundTrips) {
  const Plan plan =
      MakePlan(kExamples + "/paper_example1.lscene", kExamples + "/paper_example1.lcap", 9);
  const nlohmann::json j = PlanToJson(plan);
  for (const SchemaIssue& issue : JsonSchema::Get("plan.schema.json").Validate(j))
    ADD_FAILURE() << issue.pointer << ": " << issue.message;
  const Plan back = PlanFromJson(j, "plan.json");
  ASSERT_EQ(back.frames.size(), plan.frames.size());
  ASSERT_EQ(back.objects.size(), plan.objects.size());
  EXPECT_EQ(back.objects[3].position, plan.objects[3].position);
  EXPECT_EQ(back.classes.size(), plan.classes.size());
  for (size_t k = 0; k < plan.frames.size(); ++k) {
    EXPECT_TRUE(back.frames[k].cam_from_world.rotation.isApprox(
                    plan.frames[k].cam_from_world.rotation, 1e-12) ||
                back.frames[k].cam_from_world.rotation.coeffs().isApprox(
                    -plan.frames[k].cam_from_world.rotation.coeffs(), 1e-12));
    EXPECT_EQ(back.frames[k].changes.size(), plan.frames[k].changes.size());
  }
  nlohmann::json bad = j;
  bad["frames"][2]["camera"]["fx"] = -1;
  try {
    PlanFromJson(bad, "plan.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("plan.json#/frames/2/camera/fx"), std::string::npos)
        << e.what();
  }
}

TEST(LangPlan, DefaultCaptureIsOneNadirFrameOverTheScene) {
  const Plan plan = PlanText("LSCENE = ONE(W)\nW = terrain{size:[100,60]}\n", "", 0);
  ASSERT_EQ(plan.frames.size(), 1u);
  const Eigen::Vector3d c = CameraCenterInWorld(plan.frames[0].cam_from_world);
  EXPECT_NEAR(c.head<2>().norm(), 0, 1e-9);
  EXPECT_NEAR(c.z(), 50 / std::tan(M_PI / 6), 1e-9);
  const Eigen::Vector3d axis =
      plan.frames[0].cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.z(), -1, 1e-12);
}

TEST(LangPlan, SizeAfterPositionIsAppliedAfterTheCollisionTest) {
  // The paper's trick (section 3.1): place with a large box, then apply the
  // real size: each new object's 4 m box avoided the earlier 1 m boxes, so
  // centres are >= 2.5 m apart along x or y.
  const std::string scene =
      "LSCENE = ONE(W) MANY(X, 20)\nW = terrain{size:[40,40]}\n"
      "X = object{class:cube,extent:[4,4,1],position:{ON:W},extent:[1,1,1]}\n";
  // A key twice in one body is an error in the text notation; use scale after
  // position instead.
  EXPECT_THROW(ParseSource(scene, "s", false), Error);
  const std::string scene2 =
      "LSCENE = ONE(W) MANY(X, 20)\nW = terrain{size:[40,40]}\n"
      "X = "
      "object{class:cube,extent:[4,4,1],position:{ON:W},scale:[0.25,0.25,1]}\n";
  for (uint64_t seed = 0; seed < 10; ++seed) {
    const Plan plan = PlanText(scene2, "", seed);
    for (size_t i = 0; i < plan.objects.size(); ++i) {
      EXPECT_EQ(plan.objects[i].extent, Eigen::Vector3d(1, 1, 1));
      for (size_t j = i + 1; j < plan.objects.size(); ++j) {
        const Eigen::Vector3d d = (plan.objects[i].position - plan.objects[j].position).cwiseAbs();
        EXPECT_TRUE(d.x() >= 2.5 - 1e-9 || d.y() >= 2.5 - 1e-9);
      }
    }
  }
}

TEST(LangPlan, SceneChangeSetsFramesAndDuringTimings) {
  const std::string scene =
      "LSCENE = ONE(W) MANY(O, 3)\nW = terrain{size:[20,20]}\nO = "
      "object{class:cube,position:{ON:W}}\n";
  const std::string capture =
      "LCAP = ONE(P1) ONE(SCS1) ONE(CL)\n"
      "P1 = path{waypoints:[[0,0,10],[1,0,10]]}\n"
      "SCS1 = scene_change{O:{material:gold}}\n"
      "CL = "
      "collection{CO:{move:[P1:3]},SCS1:{after:P1:1},O:{when:{frame:5},visible:"
      "false},"
      "{during:P1,offset:[[-1,-1,0],[1,1,0]]},{during:P1:2,scale:2}}\n";
  const Plan plan = PlanText(scene, capture, 8);
  ASSERT_EQ(plan.frames.size(), 6u);
  auto count = [](const PlannedFrame& f, auto pred) {
    return std::count_if(f.changes.begin(), f.changes.end(), pred);
  };
  for (const PlannedFrame& f : plan.frames) {
    const auto material = count(f, [](const ObjectChange& c) { return c.material.has_value(); });
    const auto hidden = count(f, [](const ObjectChange& c) { return c.visible.has_value(); });
    const auto moved = count(f, [](const ObjectChange& c) { return c.position.has_value(); });
    const auto scaled = count(f, [](const ObjectChange& c) { return c.extent.has_value(); });
    EXPECT_EQ(material, f.index >= 2 ? 3 : 0) << f.index;
    EXPECT_EQ(hidden, f.index >= 5 ? 3 : 0) << f.index;
    // Three offsets, then three re-seats that keep each cube ON the terrain.
    EXPECT_EQ(moved, 6) << f.index;
    EXPECT_EQ(scaled, f.index == 2 || f.index == 3 ? 3 : 0) << f.index;
    for (const ObjectChange& c : f.changes)
      if (c.extent) {
        EXPECT_EQ(*c.extent, Eigen::Vector3d(2, 2, 2));
      }
  }
  // `during` offsets are drawn anew on every frame.
  EXPECT_NE(*plan.frames[0].changes[0].position, *plan.frames[1].changes[0].position);
}

TEST(LangPlan, InTheTerrainMeansOnIt) {
  const Plan plan = PlanText(
      "LSCENE = ONE(W) ONE(X)\nW = terrain{size:[20,20],height:{perlin:1}}\n"
      "X = object{class:cube,position:{IN:W}}\n",
      "",
      4);
  const PlannedObject& x = plan.objects[0];
  EXPECT_NEAR(
      x.position.z() - 0.5, TerrainHeight(plan.terrain, x.position.x(), x.position.y()), 1e-9);
}

TEST(LangPlan, TerrainHeightIsBoundedAndDeterministic) {
  PlannedTerrain t;
  t.present = true;
  t.perlin_amplitude = 2;
  t.perlin_seed = 5;
  double lo = 1e9, hi = -1e9;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      const double h = TerrainHeight(t, i * 0.37 - 37, j * 0.41 - 41);
      lo = std::min(lo, h);
      hi = std::max(hi, h);
    }
  EXPECT_GE(lo, -2);
  EXPECT_LE(hi, 2);
  EXPECT_GT(hi - lo, 1);
  EXPECT_EQ(TerrainHeight(t, 1.5, 2.5), TerrainHeight(t, 1.5, 2.5));
  t.perlin_frequency = 1;
  EXPECT_EQ(TerrainHeight(t, 3, 4),
            0.0);  // lattice points of the noise are zero
}

// --- The truth gate (issue: every capture yields a collection that passes) ---

namespace gate {

const char* kHills =
    "LSCENE = ONE(W) MANY(O, 3)\n"
    "W = terrain{size:[60,60],height:{perlin:{amplitude:4,frequency:0.08}}}\n"
    "O = object{class:cube,extent:[1,1,1],rotation:[0,0,[0,90]],"
    "position:{ON:W,within:[[-20,-20,-100],[20,20,100]]}}\n";

TEST(LangGate, ADoubledObjectOnHillsKeepsItsBaseOnTheSurfaceInEveryFrame) {
  const Plan plan =
      PlanText(kHills,
               "LCAP = ONE(P) ONE(CL)\n"
               "P = path{waypoints:[[0,0,40],[1,0,40],[2,0,40],[3,0,40]]}\n"
               "CL = collection{CO:{move:[P:2]},O:{after:P:1,scale:[2,2,2]},"
               "{during:P:2,rotation:[[0,30],0,[0,360]]},{during:P:2,offset:[[-3,-3,0],"
               "[3,3,0]]}}\n",
               11);
  ASSERT_EQ(plan.frames.size(), 8u);
  for (const PlannedFrame& frame : plan.frames) {
    const gen::WorldState world = gen::WorldAt(plan, frame);
    for (const gen::ObjectState& o : world.objects) {
      const double half_z = (o.world_from_object.cwiseAbs() * (0.5 * o.extent)).z();
      const double base = o.position.z() - half_z;
      const double ground = TerrainHeight(plan.terrain, o.position.x(), o.position.y());
      EXPECT_NEAR(base, ground, 1e-3) << o.planned->name << " frame " << frame.index;
      if (frame.index >= 4) {
        EXPECT_EQ(o.extent, Eigen::Vector3d(2, 2, 2));
      }
    }
  }
}

TEST(LangGate, AChangeThatMakesObjectsOverlapIsAPlanErrorAtTheChange) {
  try {
    PlanText(kHills,
             "LCAP = ONE(P) ONE(CL)\n"
             "P = path{waypoints:[[0,0,40],[1,0,40]]}\n"
             "CL = collection{CO:{move:[P:2]},O:{after:P:1,scale:[60,60,1]}}\n",
             11);
    FAIL() << "expected an overlap error";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("overlap"), std::string::npos) << e.message();
    EXPECT_EQ(e.location().line, 3) << e.location().ToString();
  }
}

TEST(LangGate, AnUndergroundCameraIsAPlanErrorNamingPathAndPose) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(O)\n"
      "W = terrain{size:[200,200],height:{perlin:{amplitude:8,frequency:0.05}}}"
      "\nO = object{class:cube,position:{ON:W,within:[[-1,-1,-100],[1,1,100]]}}"
      "\n";
  const std::string low_orbit =
      "P = path{create hemi:{cam radius:[40,40,1],obj angle:[0,360,8],"
      "cam angle:[2,2,1],center:[0,0,0]}}\n";
  try {
    PlanText(scene, "LCAP = ONE(CO) ONE(P)\nCO = camera{}\n" + low_orbit, 3);
    FAIL() << "expected a clearance error";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("P(1) pose "), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("above the terrain (height "), std::string::npos) << e.message();
    EXPECT_EQ(e.location().line, 3) << e.location().ToString();
  }
  // The explicit opt-out plans the same orbit.
  const Plan plan = PlanText(
      scene, "LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{clearance:off}}\n" + low_orbit, 3);
  EXPECT_EQ(plan.frames.size(), 8u);
}

TEST(LangGate, WaypointHeightsAboveGroundFollowTheTerrain) {
  const std::string capture =
      "LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{heights:agl}}\n"
      "P = path{waypoints:[[-10,3,12],[0,0,12],{position:[7,-4,20]}]}\n";
  const Plan plan = PlanText(kHills, capture, 11);
  ASSERT_EQ(plan.frames.size(), 3u);
  const std::vector<Eigen::Vector3d> asked = {{-10, 3, 12}, {0, 0, 12}, {7, -4, 20}};
  for (size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d eye = CameraCenterInWorld(plan.frames[k].cam_from_world);
    EXPECT_NEAR(eye.z() - TerrainHeight(plan.terrain, eye.x(), eye.y()), asked[k].z(), 1e-9);
    EXPECT_NEAR(eye.x(), asked[k].x(), 1e-9);
  }
}

TEST(LangGate, CountIntervalsAreDrawnFromTheSeed) {
  const std::string scene = "LSCENE = ONE(W)\nW = terrain{size:[100,100]}\n";
  const std::string capture = "LCAP = ONE(P)\nP = path{random:{count:[5,50],altitude:30}}\n";
  std::set<size_t> counts;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const Plan plan = PlanText(scene, capture, seed);
    EXPECT_GE(plan.frames.size(), 5u);
    EXPECT_LE(plan.frames.size(), 50u);
    counts.insert(plan.frames.size());
    EXPECT_EQ(PlanText(scene, capture, seed).frames.size(), plan.frames.size());
  }
  EXPECT_GT(counts.size(), 1u);
}

TEST(LangGate, TargetsTakeOptionalLabelsAndClassesSayWhatWasDrawn) {
  const Plan plan = PlanText(
      "LSCENE = ONE(W) ONE(K) ONE(O1) ONE(O2) ONE(O3)\n"
      "W = terrain{size:[60,60]}\nK = classes{debris:tire}\n"
      "O1 = object{class:barrel,position:{ON:W}}\n"
      "O2 = object{class:cube,position:{ON:W}}\n"
      "O3 = object{class:debris,position:{ON:W}}\n",
      "LCAP = ONE(CO) ONE(P)\nCO = camera{targets:[O1:5, O2, O3]}\n"
      "P = path{waypoints:[[0,0,50]]}\n",
      2);
  std::map<uint32_t, std::string> names;
  for (const ClassInfo& c : plan.classes) names[c.id] = c.name;
  for (const PlannedObject& o : plan.objects) {
    EXPECT_TRUE(o.target) << o.name;
    if (o.symbol == "O1") {
      EXPECT_EQ(o.class_id, 5u);
      EXPECT_EQ(names[o.class_id], "barrel");  // the label names the drawn
    }
    if (o.symbol == "O2") {
      EXPECT_EQ(names[o.class_id], "cube");
    }
    if (o.symbol == "O3") {
      EXPECT_EQ(names[o.class_id], "debris");  // the user's alias
      EXPECT_EQ(o.class_name, "tire");         // what is drawn
    }
  }
}

TEST(LangGate, AMeshKeepsItsNativeSize) {
  testing::TempDir dir;
  // A 4 x 2 x 1.5 m box as an OBJ file (metres, z up).
  std::ofstream obj(dir / "crate.obj");
  for (int k = 0; k < 8; ++k)
    obj << "v " << (k & 1 ? 2 : -2) << " " << (k & 2 ? 1 : -1) << " " << (k & 4 ? 1.5 : 0) << "\n";
  obj << "f 1 2 4\nf 1 4 3\nf 5 7 8\nf 5 8 6\nf 1 5 6\nf 1 6 2\n"
         "f 3 4 8\nf 3 8 7\nf 1 3 7\nf 1 7 5\nf 2 6 8\nf 2 8 4\n";
  obj.close();
  const std::string path = (dir / "crate.obj").string();
  const Plan plan = PlanText(
      "LSCENE = ONE(W) ONE(C) ONE(D)\nW = terrain{size:[60,60]}\n"
      "C = object{class:\"" +
          path +
          "\",position:{ON:W}}\n"
          "D = object{class:\"" +
          path + "\",unit:cm,position:{ON:W}}\n",
      "",
      2);
  ASSERT_EQ(plan.objects.size(), 2u);
  EXPECT_TRUE(plan.objects[0].extent.isApprox(Eigen::Vector3d(4, 2, 1.5)))
      << plan.objects[0].extent.transpose();
  EXPECT_TRUE(plan.objects[1].extent.isApprox(Eigen::Vector3d(0.04, 0.02, 0.015)))
      << plan.objects[1].extent.transpose();
  // The truth OBB is the mesh's bounds after the transform.
  const gen::WorldState world = gen::WorldAt(plan, plan.frames[0]);
  EXPECT_TRUE(world.objects[0].Box().half_extents.isApprox(Eigen::Vector3d(2, 1, 0.75)));
}

// Every format the mesh loader reads is a class, whatever the extension's
// case: the same 4 x 2 x 1.5 m box as an upper-case OBJ and as an ASCII STL.
TEST(LangGate, EveryMeshFormatTheLoaderReadsIsAClass) {
  testing::TempDir dir;
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? 2 : -2, k & 2 ? 1 : -1, k & 4 ? 1.5 : 0);
  const int faces[12][3] = {{1, 2, 4},
                            {1, 4, 3},
                            {5, 7, 8},
                            {5, 8, 6},
                            {1, 5, 6},
                            {1, 6, 2},
                            {3, 4, 8},
                            {3, 8, 7},
                            {1, 3, 7},
                            {1, 7, 5},
                            {2, 6, 8},
                            {2, 8, 4}};
  std::ofstream obj(dir / "Crate.OBJ"), stl(dir / "crate.stl");
  for (const Eigen::Vector3d& c : corners)
    obj << "v " << c.x() << " " << c.y() << " " << c.z() << "\n";
  stl << "solid crate\n";
  for (const auto& f : faces) {
    obj << "f " << f[0] << " " << f[1] << " " << f[2] << "\n";
    stl << "facet normal 0 0 0\nouter loop\n";
    for (int v : f) {
      const Eigen::Vector3d& c = corners[v - 1];
      stl << "vertex " << c.x() << " " << c.y() << " " << c.z() << "\n";
    }
    stl << "endloop\nendfacet\n";
  }
  stl << "endsolid crate\n";
  obj.close();
  stl.close();
  for (const char* name : {"Crate.OBJ", "crate.stl"}) {
    const std::string path = (dir / name).string();
    const Plan plan = PlanText(
        "LSCENE = ONE(W) ONE(C)\nW = terrain{size:[60,60]}\n"
        "C = object{class:\"" +
            path + "\",position:{ON:W}}\n",
        "",
        1);
    ASSERT_EQ(plan.objects.size(), 1u) << name;
    EXPECT_EQ(plan.objects[0].class_name, path) << name;
    EXPECT_TRUE(plan.objects[0].extent.isApprox(Eigen::Vector3d(4, 2, 1.5)))
        << name << ": " << plan.objects[0].extent.transpose();
  }
  // Not a mesh: the message lists every format.
  try {
    PlanText(
        "LSCENE = ONE(W) ONE(C)\nW = terrain{size:[60,60]}\n"
        "C = object{class:\"crate.txt\",position:{ON:W}}\n",
        "",
        1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(".obj .ply .gltf .glb .fbx .stl .dae .3ds .off"),
              std::string::npos)
        << e.what();
  }
}

// Every key of LCAP and LSCENE over time, in the text notation and in
// the JSON form `--emit-json` prints: the plans are identical.
TEST(LangGate, TheKeysOfLcapOverTimePlanTheSameInTextAndJson) {
  const std::string scene =
      "LSCENE = ONE(G) ONE(S) ONE(DL) ONE(A) ONE(SL) ONE(W) ONE(CAR) "
      "MANY(O, 4) ONE(T)\n"
      "G = georeference{latitude:47.3769,longitude:8.5417,altitude:408}\n"
      "S = skybox{color:blue,clouds:{type:cumulus,density:[0.1,0.3]}}\n"
      "DL = light{date:\"2026-06-21\",time:\"08:00\",utc_offset:2}\n"
      "A = atmosphere{visibility:[2000,8000]}\nSL = skylight{intensity:0.3}\n"
      "W = terrain{size:[120,120],height:{perlin:{amplitude:2}},material:"
      "grassy}\n"
      "K = classes{debris:tire}\n"
      "CAR = object{class:cube,extent:[2,1,1],position:{ON:W,within:[[-30,-2,"
      "-99],[-26,2,99]]}}\n"
      "O = object{class:{rock:0.5,barrel:0.5},position:{ON:W,within:[[0,0,-99],"
      "[20,20,99]]}}\n"
      "T = object{class:barrel,position:{ON:W,within:[[-10,-10,-99],[-6,-6,99]]"
      "}}\n";
  const std::string capture =
      "LCAP = ONE(CO) ONE(P) ONE(F) ONE(ROAD) ONE(CL1) ONE(CL2)\n"
      "CO = camera{csettings:{fov:70,res:[64,48],fps:4,clearance:2,heights:agl},"
      "targets:[CAR,O,T:7],capture:{layers:[rgb,depth,motion],folder:run_a}}\n"
      "P = create path{increment point:{start:[-10,-10,30],step:[10,10,0],"
      "count:[2,2,1]}}\n"
      "F = path{waypoints:{points:[[0,-20,25],[10,0,30],{position:[20,10,25],"
      "look_at:T}],speed:[8,12],interpolation:spline}}\n"
      "ROAD = path{waypoints:{points:[[-28,-3,0],[-3,-3,0],[-3,28,0]],speed:6,"
      "interpolation:linear}}\n"
      "SCS1 = scene change{O:{material:rust},S:{clouds:{type:stratus,density:"
      "0.7}}}\n"
      "CL1 = collection{CO:{move:[P]},DL:{during:P,azimuth:[0,360]},"
      "A:{after:1,visibility:500},SL:{frame:2,intensity:0.1},"
      "W:{after:P,material:sandy},T:{after:2,class:debris}}\n"
      "CL2 = collection{CO:{move:[F:2]},SCS1:{after:CL1},O:{during:F:2,"
      "rescatter:true},CAR:{after:CL1,move:[ROAD:2],heading:true},"
      "DL:{after:F:1,time:\"16:00\"}}\n";
  const SourceFile text_scene = ParseSource(scene, "s.lscene", false);
  const SourceFile text_capture = ParseSource(capture, "c.lcap", false);
  const SourceFile json_scene = ParseSource(SourceToJson(text_scene).dump(2), "s.json", true);
  const SourceFile json_capture = ParseSource(SourceToJson(text_capture).dump(2), "c.json", true);
  auto without_sources = [](const Plan& plan) {
    nlohmann::json j = PlanToJson(plan);
    j.erase("scene_source");
    j.erase("capture_source");
    return j;
  };
  for (uint64_t seed : {0ull, 7ull}) {
    const Plan from_text = MakePlanFromSources(text_scene, &text_capture, seed);
    const Plan from_json = MakePlanFromSources(json_scene, &json_capture, seed);
    EXPECT_EQ(without_sources(from_text), without_sources(from_json)) << "seed " << seed;
    // The keys took effect (the comparison is not between two empty plans).
    ASSERT_GT(from_text.frames.size(), 10u);
    EXPECT_EQ(from_text.capture_settings["folder"], "run_a");
    bool swapped = false, moved = false, rescattered = false;
    for (const PlannedFrame& f : from_text.frames)
      for (const ObjectChange& c : f.changes) {
        swapped |= c.asset.has_value() && *c.asset == "tire";
        moved |= c.velocity.has_value() && c.velocity->norm() > 5.9;
        rescattered |= c.object.rfind("O#", 0) == 0 && c.position.has_value();
      }
    EXPECT_TRUE(swapped && moved && rescattered);
    EXPECT_TRUE(from_text.frames.back().environment.has_value());
    // The plan's JSON form declares the new change fields and reads back.
    const nlohmann::json j = PlanToJson(from_text);
    for (const SchemaIssue& issue : JsonSchema::Get("plan.schema.json").Validate(j))
      ADD_FAILURE() << issue.pointer << ": " << issue.message;
    const nlohmann::json back = PlanToJson(PlanFromJson(j, "plan.json"));
    for (size_t k = 0; k < j["frames"].size(); ++k)
      EXPECT_EQ(back["frames"][k]["changes"], j["frames"][k]["changes"]);
  }
}

}  // namespace gate

}  // namespace
}  // namespace lsds
