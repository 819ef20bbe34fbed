// Placement zones (docs/languages.md, "Position: Algorithm 1"): what stands ON or IN an invisible
// object spreads over the zone's footprint and stands on the ground under it, wherever the zone's
// own constraints put the zone (a zone placed at one point, a zone AROUND a reference).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "generator/lang/planner.h"
#include "generator/plan/terrain_height.h"

namespace lsds {
namespace {

Plan PlanScene(const std::string& scene) {
  return MakePlanFromSources(ParseSource(scene, "s.lscene", false), nullptr, 1);
}

// A 24 x 24 m zone whose centre is pinned at (20, 20); 40 bushes ON it, 10 cubes IN it.
const std::string kZoneScene =
    "LSCENE = ONE(W) ONE(Z) MANY(B, 40) MANY(C, 10)\n"
    "W = terrain{size:[200,200]}\n"
    "Z = object{class:cube,extent:[24,24,5],visible:false,"
    "position:{ON:W,within:[[20,20,-50],[20,20,50]]}}\n"
    "B = object{class:bush,extent:[1,1,1],position:{ON:Z},overlap:true}\n"
    "C = object{class:cube,extent:[1,1,1],position:{IN:Z},overlap:true}\n";

struct Spread {
  double lo_x = 1e9, hi_x = -1e9, lo_y = 1e9, hi_y = -1e9;
  double lo_base = 1e9, hi_base = -1e9;  // base height above the terrain under the centre
};

Spread SpreadOf(const Plan& plan, const std::string& symbol) {
  Spread s;
  for (const PlannedObject& o : plan.objects) {
    if (o.symbol != symbol) continue;
    s.lo_x = std::min(s.lo_x, o.position.x());
    s.hi_x = std::max(s.hi_x, o.position.x());
    s.lo_y = std::min(s.lo_y, o.position.y());
    s.hi_y = std::max(s.hi_y, o.position.y());
    const double base = o.position.z() - 0.5 * o.extent.z() -
                        TerrainHeight(plan.terrain, o.position.x(), o.position.y());
    s.lo_base = std::min(s.lo_base, base);
    s.hi_base = std::max(s.hi_base, base);
  }
  return s;
}

TEST(LangZones, WhatStandsOnAPinnedZoneSpreadsOverItsFootprint) {
  const Plan plan = PlanScene(kZoneScene);
  const Spread on = SpreadOf(plan, "B");
  // Every centre inside the footprint [8, 32] shrunk by the half-width 0.5 ...
  EXPECT_GE(on.lo_x, 8.5);
  EXPECT_LE(on.hi_x, 31.5);
  EXPECT_GE(on.lo_y, 8.5);
  EXPECT_LE(on.hi_y, 31.5);
  // ... and spread over it: 40 uniform draws on 23 m leave the extremes within 6 m of each edge
  // (each misses a 6 m band with probability (17/23)^40 < 1e-5).
  EXPECT_LT(on.lo_x, 14.5);
  EXPECT_GT(on.hi_x, 25.5);
  EXPECT_LT(on.lo_y, 14.5);
  EXPECT_GT(on.hi_y, 25.5);
  EXPECT_NEAR(on.lo_base, 0, 1e-9);  // on the ground, not on the zone's top
  EXPECT_NEAR(on.hi_base, 0, 1e-9);
}

TEST(LangZones, WhatIsInAZoneStandsOnTheGroundInsideIt) {
  const Plan plan = PlanScene(kZoneScene);
  const Spread in = SpreadOf(plan, "C");
  EXPECT_GE(in.lo_x, 8.5);
  EXPECT_LE(in.hi_x, 31.5);
  EXPECT_NEAR(in.lo_base, 0, 1e-9);  // not floating in the zone's 5 m of height
  EXPECT_NEAR(in.hi_base, 0, 1e-9);
  for (const PlannedObject& o : plan.objects)
    if (o.symbol == "C") {
      ASSERT_EQ(o.support, PlannedObject::Support::kTerrain) << o.name;
      EXPECT_EQ(o.supports, (std::vector<std::string>{"Z"})) << o.name;
    }
}

TEST(LangZones, ThePapersLargeZoneAroundAReferenceSpreadsItsClutter) {
  // The paper's Example LSCENE 1 with its 1000 x 1000 helper box AROUND O1 (10 m margin): the
  // clutter lies anywhere on the 201 m terrain inside the box, not within 10 m of O1.
  const Plan plan = PlanScene(
      "LSCENE = ONE(W) ONE(O1) ONE(IO1) MANY(O2, 60)\n"
      "W = terrain{size:[201,201],height:{Perlin:0.2}}\n"
      "O1 = object{class:barrel,position:{ON:W}}\n"
      "IO1 = object{class:cube,visibility:false,extent:[1000,1000,1],position:{ON:W,AROUND:O1}}\n"
      "O2 = object{class:{bush:0.2,rock:0.8},overlap:true,position:{ON:IO1}}\n");
  Eigen::Vector2d o1 = Eigen::Vector2d::Zero();
  for (const PlannedObject& o : plan.objects)
    if (o.symbol == "O1") o1 = o.position.head<2>();
  double farthest = 0;
  for (const PlannedObject& o : plan.objects)
    if (o.symbol == "O2") {
      farthest = std::max(farthest, (o.position.head<2>() - o1).norm());
      EXPECT_LE(std::abs(o.position.x()), 100.5);
      EXPECT_LE(std::abs(o.position.y()), 100.5);
    }
  EXPECT_GT(farthest, 50);
}

}  // namespace
}  // namespace lsds
