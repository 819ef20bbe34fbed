// Spatial relations of LSCENE placement (issue 15): NEAR, FACING, BEHIND and
// IN FRONT OF hold on every placed copy, in text and JSON alike, and bad uses
// fail at their place.
#include <gtest/gtest.h>

#include <cmath>

#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"

namespace lsds {
namespace {

// A reference T turned by 30 degrees, then copies related to it.
const std::string kScene =
    "LSCENE = ONE(W) ONE(T) MANY(N, 15) MANY(F, 10) MANY(B, 10) MANY(FR, 10) MANY(P, 5)\n"
    "W = terrain{size:[80,80],height:{perlin:1}}\n"
    "T = object{class:person,rotation:[0,0,30],position:{ON:W}}\n"
    "N = object{class:barrel,overlap:true,position:{ON:W,NEAR:{T:6}}}\n"
    "F = object{class:jerrycan,rotation:[0,10,[0,360]],overlap:true,"
    "position:{ON:W,NEAR:{T:[5,12]},FACING:T}}\n"
    "B = object{class:tire,overlap:true,position:{ON:W,BEHIND:{T:15}}}\n"
    "FR = object{class:rock,overlap:true,position:{ON:W,IN FRONT OF:T}}\n"
    "P = object{class:cube,overlap:true,position:{ON:W,FACING:[10,-5]}}\n";

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
