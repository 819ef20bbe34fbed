// Spatial relations of LSCENE placement (docs/languages.md, "Position: Algorithm 1"): NEAR, FACING,
// BEHIND and IN FRONT OF hold on every placed copy, in text and JSON alike, and bad uses fail at
// their place.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "libs/geometry/oriented_box.h"
#include "tests/build_paths.h"

namespace lsds {
namespace {

// A reference T turned by 30 degrees, then copies related to it.
const std::string kScene =
    "LSCENE = ONE(W) ONE(T) MANY(N, 15) MANY(F, 10) MANY(B, 10) MANY(FR, 10) MANY(P, 5) MANY(VF, "
    "3)\n"
    "W = terrain{size:[80,80],height:{perlin:1}}\n"
    "T = object{class:person,rotation:[0,0,30],position:{ON:W}}\n"
    "N = object{class:barrel,overlap:true,position:{ON:W,NEAR:{T:6}}}\n"
    "F = object{class:jerrycan,rotation:[0,10,[0,360]],overlap:true,"
    "position:{ON:W,NEAR:{T:[5,12]},FACING:T}}\n"
    "B = object{class:tire,overlap:true,position:{ON:W,BEHIND:{T:15}}}\n"
    "FR = object{class:rock,overlap:true,position:{ON:W,IN FRONT OF:T}}\n"
    "P = object{class:cube,overlap:true,position:{ON:W,FACING:[10,-5]}}\n"
    "VF = object{class:cone,position:{ON:W,NEAR:{T:20},VISIBLE FROM:T}}\n";

Plan PlanOf(const std::string& text, uint64_t seed, bool as_json = false) {
  SourceFile s = ParseSource(text, "s.lscene", false);
  if (as_json) s = ParseSource(SourceToJson(s).dump(2), "s.json", true);
  return MakePlanFromSources(s, nullptr, seed);
}

std::string ErrorOf(const std::string& text) {
  try {
    PlanOf(text, 1);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

double Bearing(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  return std::atan2(to.y() - from.y(), to.x() - from.x());
}
double Heading(const PlannedObject& o) {
  return std::atan2(o.world_from_object(1, 0), o.world_from_object(0, 0));
}
double AngleGap(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

TEST(LangRelations, EveryCopyHoldsItsRelation) {
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const Plan plan = PlanOf(kScene, seed);
    const PlannedObject* t = nullptr;
    for (const PlannedObject& o : plan.objects)
      if (o.symbol == "T") t = &o;
    ASSERT_NE(t, nullptr);
    const Eigen::Vector2d forward(std::cos(M_PI / 6), std::sin(M_PI / 6));
    std::map<std::string, int> copies;
    for (const PlannedObject& o : plan.objects) {
      ++copies[o.symbol];
      const Eigen::Vector2d offset = (o.position - t->position).head<2>();
      if (o.symbol == "N") {
        EXPECT_LE(offset.norm(), 6.0) << o.name << " seed " << seed;
      }
      if (o.symbol == "F") {
        EXPECT_LE(offset.norm(), 12.0) << o.name;
        EXPECT_LT(AngleGap(Heading(o), Bearing(o.position, t->position)), 1e-9) << o.name;
        // FACING turns about the vertical only: the drawn pitch stays.
        EXPECT_NEAR(std::asin(-o.world_from_object(2, 0)), 10 * M_PI / 180, 1e-9) << o.name;
      }
      if (o.symbol == "P") {
        EXPECT_LT(AngleGap(Heading(o), Bearing(o.position, Eigen::Vector3d(10, -5, 0))), 1e-9);
      }
      if (o.symbol == "B") {
        EXPECT_LT(offset.dot(forward), 0) << o.name;
        EXPECT_LE(offset.norm(), 15.0) << o.name;
      }
      if (o.symbol == "FR") {
        EXPECT_GT(offset.dot(forward), 0) << o.name;
      }
    }
    EXPECT_EQ(copies["N"], 15);
    EXPECT_EQ(copies["F"], 10);
    EXPECT_EQ(copies["B"], 10);
    EXPECT_EQ(copies["FR"], 10);
    EXPECT_EQ(copies["VF"], 3);
  }
}

TEST(LangRelations, TextAndJsonGiveTheSamePlanAndTheSameSeedTheSameBytes) {
  for (uint64_t seed : {3ull, 11ull}) {
    nlohmann::json text = PlanToJson(PlanOf(kScene, seed));
    nlohmann::json json = PlanToJson(PlanOf(kScene, seed, true));
    nlohmann::json again = PlanToJson(PlanOf(kScene, seed));
    text.erase("scene_source");
    json.erase("scene_source");
    again.erase("scene_source");
    EXPECT_EQ(text, json) << "seed " << seed;
    EXPECT_EQ(text.dump(), again.dump());
  }
}

// A 6 m wall at x = 0 between the eyes (a point, a tower) at x = -10 and the
// space x in [1, 4]:
// a copy is seen only round the wall's ends. The check walks the segment
// independently of the placement's slab test.
TEST(LangRelations, VisibleFromKeepsTheLineOfSightClearOfEarlierBoxes) {
  const std::string scene =
      "LSCENE = ONE(WALL) ONE(TOWER) MANY(V, 12) MANY(S, 4)\n"
      "WALL = object{class:cube,extent:[1,20,6],position:{within:[[-0.5,-10,0],[0.5,10,6]]}}\n"
      "TOWER = object{class:cube,extent:[2,2,12],position:{within:[[-11,-4,0],[-9,-2,12]]}}\n"
      "V = object{class:barrel,overlap:true,retries:2000,position:{within:[[1,0,0],[4,15,1]],"
      "VISIBLE FROM:[-10,5,3]}}\n"
      "S = object{class:cube,overlap:true,retries:2000,position:{within:[[1,-15,0],[4,0,1]],"
      "VISIBLE FROM:TOWER}}\n";
  for (uint64_t seed = 0; seed < 10; ++seed) {
    const Plan plan = PlanOf(scene, seed);
    const PlannedObject* wall = nullptr;
    int seen = 0, round_the_end = 0;
    for (const PlannedObject& o : plan.objects) {
      if (o.symbol == "WALL") wall = &o;
      if (o.symbol != "V" && o.symbol != "S") continue;
      ASSERT_NE(wall, nullptr);
      OrientedBox box;
      box.center = wall->position;
      box.half_extents = 0.5 * wall->extent;
      const Eigen::Vector3d eye = o.symbol == "V"
                                      ? Eigen::Vector3d(-10, 5, 3)
                                      : Eigen::Vector3d(-10, -3, 6);  // the tower's centre
      for (int k = 1; k < 2000; ++k)
        ASSERT_FALSE(box.Contains(eye + (o.position - eye) * (k / 2000.0), -1e-6)) << o.name;
      ++seen;
      // Where the sight line crosses the wall's plane it is beyond the wall's end.
      const double t_at_wall = -eye.x() / (o.position.x() - eye.x());
      const double y_at_wall = eye.y() + t_at_wall * (o.position.y() - eye.y());
      if (std::abs(y_at_wall) >= 10 - 1e-6) ++round_the_end;
    }
    EXPECT_EQ(seen, 16);
    EXPECT_EQ(round_the_end, 16);
  }
  // A space wholly hidden: the draws run out and say so.
  const std::string hidden =
      "LSCENE = ONE(WALL) ONE(V)\n"
      "WALL = object{class:cube,extent:[1,20,6],position:{within:[[-0.5,-10,0],[0.5,10,6]]}}\n"
      "V = object{class:barrel,retries:10,position:{within:[[2,-2,-1],[4,2,1]],"
      "VISIBLE FROM:[-10,0,3]}}\n";
  EXPECT_NE(ErrorOf(hidden).find("satisfying VISIBLE_FROM:[-10,0,3] after 10 retries"),
            std::string::npos)
      << ErrorOf(hidden);
}

// The example a user starts from plans on several seeds and keeps its relations.
TEST(LangRelations, TheCheckpointExampleHoldsItsRelations) {
  const SourceFile scene =
      LoadSource(::lsds::testing::ExamplesDir() + "/checkpoint_relations.lscene");
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const Plan plan = MakePlanFromSources(scene, nullptr, seed);
    const PlannedObject* truck = nullptr;
    std::map<std::string, int> copies;
    for (const PlannedObject& o : plan.objects) {
      ++copies[o.symbol];
      if (o.symbol == "TRUCK") truck = &o;
      if (!truck) continue;
      const Eigen::Vector2d forward = truck->world_from_object.col(0).head<2>().normalized();
      const Eigen::Vector2d offset = (o.position - truck->position).head<2>();
      if (o.symbol == "GUARD") {
        EXPECT_LE(offset.norm(), 8.0);
        EXPECT_LT(AngleGap(Heading(o), Bearing(o.position, truck->position)), 1e-9);
      }
      if (o.symbol == "CAN") {
        EXPECT_LT(offset.dot(forward), 0);
      }
      if (o.symbol == "CONE") {
        EXPECT_GT(offset.dot(forward), 0);
      }
    }
    EXPECT_EQ(copies["GUARD"], 3);
    EXPECT_EQ(copies["CAN"], 4);
    EXPECT_EQ(copies["CONE"], 5);
    EXPECT_EQ(copies["HIDDEN"], 1);
  }
}

TEST(LangRelations, BadUsesFailAtTheirPlace) {
  const std::string head =
      "LSCENE = ONE(W) ONE(T) ONE(X)\nW = terrain{size:[40,40]}\n"
      "T = object{class:person,position:{ON:W}}\n";
  std::string e = ErrorOf(head + "X = object{class:cube,position:{ON:W,NEAR:Q}}\n");
  EXPECT_NE(e.find("s.lscene:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("undefined symbol 'Q'"), std::string::npos) << e;
  e = ErrorOf(head + "X = object{class:cube,position:{ON:W,NEAR:{T:far}}}\n");
  EXPECT_NE(e.find("s.lscene:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number"), std::string::npos) << e;
  e = ErrorOf(head + "X = object{class:cube,position:{ON:W,BEHIND:{T:-2}}}\n");
  EXPECT_NE(e.find("BEHIND distance must be >= 0"), std::string::npos) << e;
  e = ErrorOf(head + "X = object{class:cube,position:{ON:W,FACING:[1,\"a\"]}}\n");
  EXPECT_NE(e.find("s.lscene:4:"), std::string::npos) << e;
  e = ErrorOf(head + "X = object{class:cube,position:{ON:W,VISIBLE FROM:[1,2]}}\n");
  EXPECT_NE(e.find("VISIBLE FROM takes an object or a point [x, y, z]"), std::string::npos) << e;
  e = ErrorOf(head + "X = object{class:cube,position:{ON:W,FACING:W}}\n");
  EXPECT_NE(e.find("expected an object"), std::string::npos) << e;
  // Nothing of the space lies behind T: the draws run out and say which relation.
  e = ErrorOf(
      "LSCENE = ONE(W) ONE(T) ONE(X)\nW = terrain{size:[40,40]}\n"
      "T = object{class:person,position:{within:[[-1,-1,0],[1,1,2]]}}\n"
      "X = object{class:cube,retries:5,position:{BEHIND:T,within:[[5,-20,0],[20,20,1]]}}\n");
  EXPECT_NE(e.find("satisfying BEHIND:T after 5 retries"), std::string::npos) << e;
  // NEAR of an object out of the space: the box is empty, said at NEAR.
  e = ErrorOf(
      "LSCENE = ONE(W) ONE(T) ONE(X)\nW = terrain{size:[40,40]}\n"
      "T = object{class:person,position:{within:[[-1,-1,0],[1,1,2]]}}\n"
      "X = object{class:cube,position:{within:[[10,10,0],[20,20,1]],NEAR:{T:3}}}\n");
  EXPECT_NE(e.find("empty after NEAR:T"), std::string::npos) << e;
}

}  // namespace
}  // namespace lsds
