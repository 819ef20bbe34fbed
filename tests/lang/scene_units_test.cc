// The units of the LSCENE evaluator (generator/lang/scene/), each on its own with inputs whose
// answer is known: the check, the assets a class names, the class table, the ground, the placed
// objects and Algorithm 1 (position).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "generator/lang/capture/targets.h"
#include "generator/lang/scene/class_catalog.h"
#include "generator/lang/scene/class_table.h"
#include "generator/lang/scene/ground.h"
#include "generator/lang/scene/placed_objects.h"
#include "generator/lang/scene/position.h"
#include "generator/lang/scene/scene_check.h"
#include "generator/lang/source.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/geodesy.h"
#include "libs/util/error.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

// A parsed LSCENE text; kept in place, as its program points into its source.
struct Scene {
  explicit Scene(const std::string& text, const std::string& path = "s.lscene")
      : src(ParseSource(text, path, false)), program(ReadProgram(src, "LSCENE")) {}
  const Definition& Def(const std::string& symbol) const { return *program.Find(symbol); }
  SourceFile src;
  Program program;
};

using testing::ErrorOf;

// ---- scene_check.h

TEST(SceneCheck, LearnsTheTerrainAliasesAndStartRuleCounts) {
  Scene s(
      "LSCENE = ONE(T) MANY(B) MANY(C, 3)\nT = terrain{size:[100,100]}\n"
      "classes = classes{shrub:bush}\nB = object{class:shrub}\nC = object{class:cube}\n");
  ClassCatalog assets(s.program);
  const SceneSymbols symbols = CheckScene(s.program, &assets);
  EXPECT_EQ(symbols.terrain, "T");
  EXPECT_EQ(symbols.many_without_count, std::set<std::string>{"B"});
  ASSERT_TRUE(symbols.start_counts.count("C"));
  EXPECT_TRUE(bool(symbols.start_counts.at("C")));
  EXPECT_EQ(assets.Resolve(s.Def("B").body, "shrub").asset, "bush");
}

TEST(SceneCheck, AForwardReferenceIsALocatedError) {
  Scene s(
      "LSCENE = ONE(A) ONE(B)\nA = object{class:cube,position:{ON:B}}\nB = object{class:cube}\n");
  ClassCatalog assets(s.program);
  const std::string e = ErrorOf([&] { CheckScene(s.program, &assets); });
  EXPECT_NE(e.find("s.lscene:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("A refers to 'B' before its definition"), std::string::npos) << e;
}

// ---- class_catalog.h

TEST(ClassCatalog, ResolvesBuiltinsAliasesAndMeshesNextToTheScene) {
  Scene s("LSCENE = ONE(A)\nA = object{class:cube}\n", "dir/s.lscene");
  ClassCatalog assets(s.program);
  assets.AddAlias("V", "cars");  // a built-in's other spelling
  const Node& where = s.Def("A").body;
  EXPECT_EQ(assets.Resolve(where, "rocks").asset, "rock");
  const SceneClass alias = assets.Resolve(where, "V");
  EXPECT_EQ(alias.asset, "car");
  EXPECT_EQ(alias.name, "V");
  EXPECT_EQ(assets.Resolve(where, "m/tank.obj").asset, "dir/m/tank.obj");
  const std::string e = ErrorOf([&] { assets.Resolve(where, "cub"); });
  EXPECT_NE(e.find("unknown class 'cub'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'cube'"), std::string::npos) << e;
}

TEST(ClassCatalog, NaturalExtentOfABuiltinAndOfAMeshInItsUnit) {
  const testing::TempDir dir;
  const std::string mesh = (dir / "pipe.obj").string();
  std::ofstream(mesh) << "v 0 0 0\nv 300 0 0\nv 0 20 0\nv 0 0 40\nf 1 2 3\nf 1 2 4\n";
  Scene s("LSCENE = ONE(A)\nA = object{class:cube}\n");
  ClassCatalog assets(s.program);
  const Node& where = s.Def("A").body;
  EXPECT_EQ(assets.NaturalExtent("car", 1.0, where, "A"), BuiltinClasses().at("car"));
  const Eigen::Vector3d in_cm = assets.NaturalExtent(mesh, 0.01, where, "A");
  EXPECT_NEAR((in_cm - Eigen::Vector3d(3, 0.2, 0.4)).norm(), 0, 1e-12);
  // Read as metres without a unit, 300 m is no object: the unit is asked for.
  const std::string undeclared =
      ErrorOf([&] { assets.NaturalExtent(mesh, std::nullopt, where, "A"); });
  EXPECT_NE(undeclared.find("s.lscene:2:"), std::string::npos) << undeclared;
  EXPECT_NE(undeclared.find("is 300 x 20 x 40 in its own units"), std::string::npos) << undeclared;
  EXPECT_NE(undeclared.find("unit:cm"), std::string::npos) << undeclared;
  // Through the language: unit:cm gives the 3 m pipe.
  const Plan plan = testing::PlanText("LSCENE = ONE(P)\nP = object{class:\"" + mesh +
                                          "\",unit:cm,position:{within:[[0,0,0],[10,10,10]]}}\n",
                                      "");
  ASSERT_EQ(plan.objects.size(), 1u);
  EXPECT_NEAR((plan.objects[0].extent - Eigen::Vector3d(3, 0.2, 0.4)).norm(), 0, 1e-12);
  EXPECT_NE(testing::PlanErrorOf("LSCENE = ONE(P)\nP = object{class:\"" + mesh + "\"}\n")
                .find("give the unit it is modelled in"),
            std::string::npos);
  const std::string e =
      ErrorOf([&] { assets.NaturalExtent(mesh + ".missing.obj", 1, where, "A"); });
  EXPECT_NE(e.find("s.lscene:2:"), std::string::npos) << e;
}

TEST(ClassCatalog, MetresPerUnitOfAnObject) {
  Scene s("LSCENE = ONE(A)\nA = object{class:cube,unit:cm}\nB = object{class:cube,unit:yd}\n");
  EXPECT_EQ(MetresPerUnit(s.Def("A")), 0.01);
  EXPECT_NE(ErrorOf([&] { MetresPerUnit(s.Def("B")); }).find("unit must be one of"),
            std::string::npos);
}

// ---- class_table.h

// Targets as the capture reads them (`targets:[...]`), against the scene. The capture is kept:
// the labels point into it.
TargetLabels Targets(const Scene& scene, const std::string& targets) {
  struct Capture {
    explicit Capture(const std::string& text)
        : src(ParseSource(text, "c.lcap", false)), program(ReadProgram(src, "LCAP")) {}
    SourceFile src;
    Program program;
  };
  static std::vector<std::unique_ptr<Capture>> captures;
  captures.push_back(
      std::make_unique<Capture>("LCAP = ONE(CO)\nCO = camera{targets:" + targets + "}\n"));
  return ReadTargets(captures.back()->program, scene.program);
}

TEST(SceneClassTable, TerrainFirstLabelsReservedAndAChoiceLabelledOnceOrPerClass) {
  Scene s(
      "LSCENE = ONE(T) ONE(A) ONE(V)\nT = terrain{size:[100,100]}\nA = "
      "object{class:{bush:1,rock:1}}\n"
      "V = object{class:{car:0.5,truck:0.5}}\n");
  ClassCatalog catalog(s.program);
  // V:2 labels whatever V draws 2 (the paper's per-pixel label); the scene's ids skip it.
  Plan plan;
  const TargetClassIds labelled = AssignClassIds(s.program, catalog, Targets(s, "[V:2]"), &plan);
  const std::vector<std::pair<uint32_t, std::string>> expected = {
      {1, "terrain"}, {2, "car|truck"}, {3, "bush"}, {4, "rock"}};
  ASSERT_EQ(plan.classes.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(plan.classes[i].id, expected[i].first);
    EXPECT_EQ(plan.classes[i].name, expected[i].second);
  }
  EXPECT_EQ(ClassIdOf(plan, labelled, "V", "truck"), 2u);
  EXPECT_EQ(ClassIdOf(plan, labelled, "A", "rock"), 4u);
  EXPECT_EQ(ClassIdOf(plan, labelled, "A", "tire"), 0u);
  // Labelled per class, the classes stay apart.
  Plan per_class;
  const TargetClassIds listed =
      AssignClassIds(s.program, catalog, Targets(s, "[V:{truck:7,car:9}]"), &per_class);
  EXPECT_EQ(ClassIdOf(per_class, listed, "V", "truck"), 7u);
  EXPECT_EQ(ClassIdOf(per_class, listed, "V", "car"), 9u);
  EXPECT_EQ(per_class.classes.back().name, "car");
  // Two targets with one id: one class, named after both.
  Plan shared;
  AssignClassIds(s.program, catalog, Targets(s, "[V:{car:5,truck:6},A:5]"), &shared);
  ASSERT_EQ(shared.classes.size(), 3u);  // terrain, 5, 6
  EXPECT_EQ(shared.classes[1].id, 5u);
  EXPECT_EQ(shared.classes[1].name, "bush|rock|car");
  // A class the label misses, a class the symbol never draws.
  Plan bad;
  const std::string missing =
      ErrorOf([&] { AssignClassIds(s.program, catalog, Targets(s, "[V:{car:1}]"), &bad); });
  EXPECT_NE(missing.find("c.lcap:2:"), std::string::npos) << missing;
  EXPECT_NE(missing.find("V may draw 'truck', which its label does not name"), std::string::npos)
      << missing;
  EXPECT_NE(ErrorOf([&] {
              AssignClassIds(s.program, catalog, Targets(s, "[V:{car:1,truck:2,bus:3}]"), &bad);
            }).find("V never draws 'bus'"),
            std::string::npos);
}

// ---- ground.h

TEST(SceneGround, TerrainAndGeoreference) {
  Scene s(
      "LSCENE = ONE(T) ONE(G)\nT = terrain{size:[200,100],perlin:{amplitude:3,frequency:0.02},"
      "seed:7,material:grass}\nG = georeference{latitude:48.1,longitude:11.5,altitude:520}\n"
      "H = georeference{latitude:48.1}\n");
  Plan plan;
  plan.classes.push_back({5, "terrain"});
  Rng rng(1);
  EvaluateTerrain(s.Def("T").body, 1, rng, &plan);
  EXPECT_TRUE(plan.terrain.present);
  EXPECT_EQ(plan.terrain.size, Eigen::Vector2d(200, 100));
  EXPECT_EQ(plan.terrain.perlin_amplitude, 3);
  EXPECT_EQ(plan.terrain.perlin_frequency, 0.02);
  EXPECT_EQ(plan.terrain.perlin_seed, 7u);
  EXPECT_EQ(plan.terrain.material, "grass");
  EXPECT_EQ(plan.terrain.class_id, 5u);
  const GeoOrigin geo = EvaluateGeoreference(s.Def("G").body, rng);
  EXPECT_EQ(geo.latitude_deg, 48.1);
  EXPECT_EQ(geo.longitude_deg, 11.5);
  EXPECT_EQ(geo.altitude_m, 520);
  const std::string e = ErrorOf([&] { EvaluateGeoreference(s.Def("H").body, rng); });
  EXPECT_NE(e.find("needs a latitude and a longitude"), std::string::npos) << e;
}

TEST(SceneGround, Wgs84InOneKeyAndObjectsPlacedByLatitudeAndLongitude) {
  const Plan plan = testing::PlanText(
      "LSCENE = ONE(G) ONE(W) ONE(O)\nG = georeference{wgs84:[47.3769,8.5417,408]}\n"
      "W = terrain{size:[400,400]}\nO = "
      "object{class:cube,position:{ON:W,wgs84:[47.3778,8.5430]}}\n",
      "");
  ASSERT_TRUE(plan.geo.has_value());
  EXPECT_EQ(plan.geo->latitude_deg, 47.3769);
  EXPECT_EQ(plan.geo->longitude_deg, 8.5417);
  EXPECT_EQ(plan.geo->altitude_m, 408);
  const Eigen::Vector3d expected = EnuOf(*plan.geo, Geodetic{47.3778, 8.5430, 408});
  // About 98 m east and 100 m north of the origin.
  EXPECT_NEAR(plan.objects[0].position.x(), expected.x(), 1e-9);
  EXPECT_NEAR(plan.objects[0].position.y(), expected.y(), 1e-9);
  EXPECT_GT(expected.x(), 90);
  EXPECT_GT(expected.y(), 90);
  EXPECT_NE(
      testing::PlanErrorOf("LSCENE = ONE(O)\nO = object{class:cube,position:{wgs84:[47,8]}}\n")
          .find("needs a georeferenced scene"),
      std::string::npos);
}

// ---- blueprints.h

TEST(SceneBlueprints, AGroupIsPlacedAsOneAndItsMembersStandOnTheGround) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(C)\nW = terrain{size:[100,100],perlin:2}\n"
      "CAMP = blueprint{TENT:{class:crate,extent:[3,2,2]},FIRE:{class:barrel,at:[4,0,0]}}\n"
      "C = object{class:CAMP,rotation:[0,0,90],position:{ON:W,within:[[-10,-10,-100],[10,10,100]]}}"
      "\n";
  const Plan plan =
      testing::PlanText(scene, "LCAP = ONE(P)\nP = path{create point:{position:[0,0,40]}}\n");
  ASSERT_EQ(plan.objects.size(), 3u);
  const PlannedObject& group = plan.objects[0];
  const PlannedObject& tent = plan.objects[1];
  const PlannedObject& fire = plan.objects[2];
  EXPECT_EQ(group.name, "C#1");
  EXPECT_FALSE(group.visible);  // the group's box: a helper
  EXPECT_EQ(tent.name, "C#1/TENT");
  EXPECT_EQ(fire.name, "C#1/FIRE");
  EXPECT_EQ(tent.class_name, "crate");
  EXPECT_EQ(tent.extent, Eigen::Vector3d(3, 2, 2));
  EXPECT_EQ(fire.extent, BuiltinClasses().at("barrel"));
  // The fire stands 4 m from the tent along the group's turned x axis.
  const Eigen::Vector3d offset = group.world_from_object * Eigen::Vector3d(4, 0, 0);
  EXPECT_NEAR((fire.position - tent.position).head<2>().norm(), 4, 1e-9);
  EXPECT_NEAR(((fire.position - tent.position).head<2>() - offset.head<2>()).norm(), 0, 1e-9);
  // Each member's base on the terrain under it; each has its class's id.
  for (const PlannedObject* o : {&tent, &fire}) {
    EXPECT_TRUE(o->visible);
    EXPECT_NEAR(o->position.z() - 0.5 * o->extent.z(),
                TerrainHeight(plan.terrain, o->position.x(), o->position.y()),
                1e-9)
        << o->name;
    bool named = false;
    for (const ClassInfo& c : plan.classes)
      named = named || (c.id == o->class_id && c.name == o->class_name);
    EXPECT_TRUE(named) << o->name;
  }
  // A member that is itself a blueprint, and an unknown class, are located errors.
  EXPECT_NE(testing::PlanErrorOf("LSCENE = ONE(C)\nA = blueprint{X:{class:cube}}\n"
                                 "B = blueprint{Y:{class:A}}\nC = object{class:B}\n")
                .find("s.lscene:3:"),
            std::string::npos);
  EXPECT_NE(testing::PlanErrorOf("LSCENE = ONE(C)\nA = blueprint{X:{class:cub}}\n"
                                 "C = object{class:A}\n")
                .find("unknown class 'cub'"),
            std::string::npos);
}

// ---- placed_objects.h

Placed PlacedBox(const std::string& symbol,
                 const Eigen::Vector3d& centre,
                 const Eigen::Vector3d& extent,
                 bool visible = true) {
  Placed p;
  p.object.symbol = symbol;
  p.object.position = centre;
  p.object.extent = extent;
  p.object.visible = visible;
  p.aabb = AabbOf(centre, Eigen::Matrix3d::Identity(), extent);
  return p;
}

TEST(ScenePlacedObjects, AZoneHandsOnTheGroundWithinItsFootprint) {
  Placed zone = PlacedBox("Z", {20, 20, 1}, {24, 24, 2}, /*visible=*/false);
  zone.has_support = true;
  zone.support = TerrainSurface(PlannedTerrain{});  // the 100 m ground plane
  const StandingSurface s = SurfaceOf(zone);
  EXPECT_EQ(s.footprint.lo.head<2>(), Eigen::Vector2d(8, 8));
  EXPECT_EQ(s.footprint.hi.head<2>(), Eigen::Vector2d(32, 32));
  EXPECT_EQ(s.top, 0);  // the ground, not the zone's top (2)
  const StandingSurface table = SurfaceOf(PlacedBox("T", {0, 0, 0.5}, {2, 1, 1}));
  EXPECT_EQ(table.top, 1);
}

TEST(ScenePlacedObjects, CollidesWithinTheLargerSeparationButNotWithItsSupport) {
  PlacedObjects placed;
  placed.Add(PlacedBox("A", {0, 0, 0.5}, {2, 2, 1}));
  Placed near = PlacedBox("B", {3.5, 0, 0.5}, {2, 2, 1});  // a gap of 1.5 m
  EXPECT_FALSE(placed.Collides(near, {}));
  near.object.separation = 2;
  EXPECT_TRUE(placed.Collides(near, {}));
  EXPECT_FALSE(placed.Collides(near, {"A"}));
  Scene s("LSCENE = ONE(A)\nA = object{class:cube}\n");
  const std::string e = ErrorOf([&] { placed.FirstCopy(s.Def("A").body, "C"); });
  EXPECT_NE(e.find("'C' has no placed copies"), std::string::npos) << e;
}

TEST(ScenePlacedObjects, ABoxBetweenEyeAndCentreBlocksTheSight) {
  PlacedObjects placed;
  placed.Add(PlacedBox("W", {5, 0, 1}, {1, 4, 2}));
  EXPECT_TRUE(placed.Blocked({0, 0, 1}, {10, 0, 1}, nullptr));
  EXPECT_FALSE(placed.Blocked({0, 0, 5}, {10, 0, 5}, nullptr));           // over the wall
  EXPECT_FALSE(placed.Blocked({0, 0, 1}, {10, 0, 1}, &placed.all()[0]));  // the viewer itself
}

// ---- position.h

struct Placing {
  explicit Placing(const std::string& text) : scene(text) {}
  bool Place(const std::string& symbol, Placed* p, const OverlapRules& rules = {}) {
    const PlacementContext context{placed, terrain_symbol, terrain, geo, rng};
    const Definition& def = scene.Def(symbol);
    p->object.symbol = symbol;
    p->object.extent = Eigen::Vector3d(2, 2, 2);
    return PlaceObject(context, def, def.body.Find("position"), 0, 1, rules, p);
  }
  Scene scene;
  PlacedObjects placed;
  std::string terrain_symbol;
  PlannedTerrain terrain;
  std::optional<GeoOrigin> geo;
  Rng rng{3};
};

TEST(ScenePosition, OnAZoneStandsOnTheGroundInsideIt) {
  Placing t(
      "LSCENE = ONE(A)\nZ = object{class:cube}\nA = object{class:cube,position:{ON:Z}}\n"
      "W = object{class:cube,position:{within:[[0,0,0],[10,10,10]]}}\n");
  Placed zone = PlacedBox("Z", {20, 20, 1}, {24, 24, 2}, /*visible=*/false);
  zone.has_support = true;
  zone.support = TerrainSurface(t.terrain);
  t.placed.Add(zone);
  for (int i = 0; i < 50; ++i) {
    Placed p;
    ASSERT_TRUE(t.Place("A", &p));
    EXPECT_GE(p.aabb.lo.x(), 8 - 1e-12);
    EXPECT_LE(p.aabb.hi.x(), 32 + 1e-12);
    EXPECT_GE(p.aabb.lo.y(), 8 - 1e-12);
    EXPECT_LE(p.aabb.hi.y(), 32 + 1e-12);
    EXPECT_NEAR(p.aabb.lo.z(), 0, 1e-12);  // on the ground
    EXPECT_EQ(p.object.support, PlannedObject::Support::kTop);
    EXPECT_EQ(p.object.supports, std::vector<std::string>{"Z"});
  }
  Placed w;
  ASSERT_TRUE(t.Place("W", &w));  // within gives z too: no ground implied
  EXPECT_EQ(w.object.support, PlannedObject::Support::kNone);
  EXPECT_GE(w.aabb.lo.z(), 0);
  EXPECT_LE(w.aabb.hi.z(), 10);
}

TEST(ScenePosition, OnTheTerrainFollowsItsHeight) {
  Placing t("LSCENE = ONE(A)\nT = terrain{}\nA = object{class:cube,position:{ON:T}}\n");
  t.terrain_symbol = "T";
  t.terrain.present = true;
  t.terrain.size = Eigen::Vector2d(50, 50);
  t.terrain.perlin_amplitude = 4;
  t.terrain.perlin_frequency = 0.05;
  Placed p;
  ASSERT_TRUE(t.Place("A", &p));
  EXPECT_EQ(p.object.support, PlannedObject::Support::kTerrain);
  EXPECT_NEAR(
      p.aabb.lo.z(), TerrainHeight(t.terrain, p.object.position.x(), p.object.position.y()), 1e-12);
}

TEST(ScenePosition, OverlapPoliciesDeleteHideOrFailLocated) {
  Placing t("LSCENE = ONE(A)\nA = object{class:cube,position:{within:[[0,0,0],[2,2,2]]}}\n");
  t.placed.Add(PlacedBox("X", {1, 1, 1}, {2, 2, 2}));  // fills the space
  Placed p;
  OverlapRules rules;
  rules.retries = 3;
  rules.on_overlap = "delete";
  EXPECT_FALSE(t.Place("A", &p, rules));
  rules.on_overlap = "hide";
  EXPECT_TRUE(t.Place("A", &p, rules));
  EXPECT_FALSE(p.object.visible);
  rules.on_overlap = "move";
  p.object.visible = true;
  const std::string e = ErrorOf([&] { t.Place("A", &p, rules); });
  EXPECT_NE(e.find("s.lscene:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("A: cannot place copy 1 of 1 without overlap after 3 retries in "
                   "[0,2]x[0,2]x[0,2]"),
            std::string::npos)
      << e;
  rules.on_overlap = "allow";
  EXPECT_TRUE(t.Place("A", &p, rules));
  EXPECT_TRUE(p.object.overlap_allowed);
}

TEST(ScenePosition, AnEmptySpaceNamesTheConstraintThatEmptiedIt) {
  Placing t(
      "LSCENE = ONE(A)\nA = object{class:cube,position:{within:[[0,0,0],[2,2,2]],"
      "AROUND:{X:1}}}\n");
  t.placed.Add(PlacedBox("X", {50, 50, 1}, {2, 2, 2}));
  Placed p;
  const std::string e = ErrorOf([&] { t.Place("A", &p); });
  EXPECT_NE(e.find("A copy 1: the position space is empty after AROUND:X"), std::string::npos) << e;
}

}  // namespace
}  // namespace lsds
