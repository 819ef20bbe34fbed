// Numeric distributions beyond the uniform interval (docs/languages.md,
// "Values"): normal, truncated normal and numeric choices {30:0.5,60:0.5} in
// the text notation, checked by their sample moments over many draws.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "generator/lang/distributions.h"
#include "generator/lang/planner.h"

namespace lsds {
namespace {

// The yaw of `n` objects drawn from `rotation`'s yaw value.
std::vector<double> Yaws(const std::string& yaw, int n = 2000) {
  const std::string scene = "LSCENE = MANY(O, " + std::to_string(n) +
                            ")\nO = object{class:cube,extent:[0.1,0.1,0.1],overlap:true,"
                            "rotation:[0,0," +
                            yaw + "]}\n";
  const Plan plan = MakePlanFromSources(ParseSource(scene, "s.lscene", false), nullptr, 7);
  std::vector<double> yaws;
  for (const PlannedObject& o : plan.objects)
    yaws.push_back(std::atan2(o.world_from_object(1, 0), o.world_from_object(0, 0)) * 180 / M_PI);
  return yaws;
}

TEST(Distributions, QuantileInvertsTheCdf) {
  for (double p : {1e-9, 1e-4, 0.01, 0.2, 0.5, 0.77, 0.999, 1 - 1e-9})
    EXPECT_NEAR(NormalCdf(NormalQuantile(p)), p, 1e-12 + 1e-9 * p) << p;
  EXPECT_NEAR(NormalQuantile(0.975), 1.959963984540054, 1e-9);
}

TEST(Distributions, NormalHasItsMeanAndDeviation) {
  const std::vector<double> v = Yaws("{normal:[20,5]}");
  double mean = 0, var = 0;
  for (double x : v) mean += x / v.size();
  for (double x : v) var += (x - mean) * (x - mean) / (v.size() - 1);
  EXPECT_NEAR(mean, 20, 0.35);  // 3 standard errors (5 / sqrt(2000) = 0.11)
  EXPECT_NEAR(std::sqrt(var), 5, 0.25);
}

TEST(Distributions, TruncatedNormalStaysInItsBoundsWithTheRightMean) {
  // N(0, 10) truncated to [0, 30]: the half-normal mean 10 sqrt(2/pi) = 7.98
  // (the mass beyond 3 sd shifts it by < 0.05).
  for (const std::string spelling : {"{normal:[0,10,0,30]}", "{truncated_normal:[0,10,0,30]}"}) {
    const std::vector<double> v = Yaws(spelling);
    double mean = 0;
    for (double x : v) {
      EXPECT_GE(x, -1e-9);
      EXPECT_LE(x, 30 + 1e-9);
      mean += x / v.size();
    }
    EXPECT_NEAR(mean, 7.98, 0.4) << spelling;
  }
}

TEST(Distributions, NumericChoiceInTextNotation) {
  std::map<long, int> counts;
  for (double x : Yaws("{30:0.5,60:0.5}")) counts[std::lround(x)]++;
  ASSERT_EQ(counts.size(), 2u);
  EXPECT_NEAR(counts[30], 1000, 100);
  EXPECT_NEAR(counts[60], 1000, 100);
}

TEST(Distributions, BadParametersAreLocated) {
  for (const auto& [yaw, expected] : std::vector<std::pair<std::string, std::string>>{
           {"{normal:[0]}", "[mean, sd]"},
           {"{normal:[0,-1]}", "standard deviation must be >= 0"},
           {"{normal:[0,1,5,5]}", "min < max"},
           {"{truncated_normal:[0,1]}", "[mean, sd, min, max]"}}) {
    try {
      Yaws(yaw, 1);
      ADD_FAILURE() << yaw;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("s.lscene:2:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace lsds
