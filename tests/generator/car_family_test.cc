// The car family (docs/generator.md, "Built-in classes"): each shape keeps its own proportions
// and has four wheels with a tyre/rim contrast; a planned car gets one shape's own size, drawn
// deterministically per seed; the paint is drawn from the palette per object; the truth follows
// the drawn mesh.
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "generator/scene/builtin_meshes.h"
#include "generator/scene/materials.h"
#include "generator/scene/object_library.h"
#include "tests/lang/plan_text.h"

namespace lsds::gen {
namespace {

Eigen::Vector3f BoundsOf(const TriangleMesh& mesh) {
  Eigen::Vector3f lo = mesh.positions.front(), hi = lo;
  for (const Eigen::Vector3f& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return hi - lo;
}

// The constant colour of each tinted part (one albedo map per part: builtin_meshes.cc), 8-bit.
std::vector<Eigen::Vector3i> PartColours(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3i> out;
  for (const auto& map : mesh.albedo_maps) {
    const Eigen::Vector3f linear = map->Sample({0.5f, 0.5f});
    Eigen::Vector3i srgb;
    for (int k = 0; k < 3; ++k) {
      const float c = linear[k];
      const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
      srgb[k] = static_cast<int>(std::lround(255 * s));
    }
    out.push_back(srgb);
  }
  return out;
}

int CountParts(const TriangleMesh& mesh, const Eigen::Vector3i& colour) {
  int n = 0;
  for (const Eigen::Vector3i& c : PartColours(mesh)) n += (c - colour).cwiseAbs().maxCoeff() <= 1;
  return n;
}

const Eigen::Vector3i kTyre(25, 25, 27), kRim(170, 172, 176);

// Designed sizes (length x width x height, metres) of the five shapes.
const std::map<std::string, Eigen::Vector3d>& DesignedSizes() {
  static const std::map<std::string, Eigen::Vector3d> sizes = {{"sedan", {4.6, 1.8, 1.45}},
                                                               {"hatchback", {4.0, 1.75, 1.5}},
                                                               {"suv", {4.7, 1.9, 1.75}},
                                                               {"pickup", {5.3, 1.9, 1.85}},
                                                               {"van", {5.0, 2.0, 2.1}}};
  return sizes;
}

TEST(CarFamily, EachShapeKeepsItsProportionsAndHasFourWheelsWithRims) {
  ASSERT_EQ(CarShapes().size(), DesignedSizes().size());
  std::set<std::string> ratios;
  for (size_t i = 0; i < CarShapes().size(); ++i) {
    const CarShape& shape = CarShapes()[i];
    SCOPED_TRACE(shape.name);
    const Eigen::Vector3d designed = DesignedSizes().at(shape.name);
    const TriangleMesh mesh = CarMesh(i);
    // The mesh's bounds are the shape's size, which is the design to 1 cm (the 20-sided tyre
    // polygon may miss its circle's lowest point by under 1 cm).
    EXPECT_TRUE(BoundsOf(mesh).cast<double>().isApprox(shape.size, 1e-6));
    EXPECT_NEAR(shape.size.x(), designed.x(), 0.01);
    EXPECT_NEAR(shape.size.y(), designed.y(), 0.01);
    EXPECT_NEAR(shape.size.z(), designed.z(), 0.01);
    // Length/width and length/height ratios as designed, to 1 %.
    EXPECT_NEAR(shape.size.x() / shape.size.y(), designed.x() / designed.y(), 0.01);
    EXPECT_NEAR(shape.size.x() / shape.size.z(), designed.x() / designed.z(), 0.01);
    char key[32];
    std::snprintf(key,
                  sizeof key,
                  "%.2f:%.2f",
                  shape.size.x() / shape.size.y(),
                  shape.size.x() / shape.size.z());
    ratios.insert(key);
    // Four dark tyres, four light rims (a luminance contrast of over 5x), one window band.
    EXPECT_EQ(CountParts(mesh, kTyre), 4);
    EXPECT_EQ(CountParts(mesh, kRim), 4);
    EXPECT_EQ(CountParts(mesh, {30, 38, 48}), 1);
    // Drawn at its own size, a car is that shape.
    EXPECT_EQ(CarShapeNearest(shape.size), i);
    EXPECT_EQ(CarShapeNearest(2.0 * shape.size), i) << "a scaled car keeps its shape";
  }
  EXPECT_EQ(ratios.size(), CarShapes().size()) << "no two shapes share proportions";
  EXPECT_EQ(CountParts(TruckMesh(), kTyre), 6);
  EXPECT_EQ(CountParts(TruckMesh(), kRim), 6);
}

TEST(CarFamily, AnObjectDrawsTheShapeOfItsExtentNormalizedToItsUnitBox) {
  for (size_t i = 0; i < CarShapes().size(); ++i) {
    const ClassShape shape = MakeClassShape("car", 5, "test", &CarShapes()[i].size);
    const TriangleMesh own = CarMesh(i);
    ASSERT_EQ(shape.mesh.positions.size(), own.positions.size()) << CarShapes()[i].name;
    EXPECT_TRUE(BoundsOf(shape.mesh).isApprox(Eigen::Vector3f::Ones(), 1e-5f));
  }
}

TEST(CarFamily, PaintIsDrawnFromThePalettePerSeedDeterministically) {
  double total = 0;
  for (const auto& [material, share] : CarPaintPalette()) {
    EXPECT_NO_THROW(FindMaterial(material, "palette"));
    total += share;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  constexpr int kCars = 20000;
  std::map<std::string, int> drawn;
  for (int seed = 0; seed < kCars; ++seed) {
    const std::string& paint = CarPaint(static_cast<uint64_t>(seed));
    EXPECT_EQ(paint, CarPaint(static_cast<uint64_t>(seed)));
    ++drawn[paint];
  }
  // Each colour's count within 5 binomial standard deviations of its share.
  for (const auto& [material, share] : CarPaintPalette()) {
    const double expected = kCars * share;
    EXPECT_NEAR(drawn[material], expected, 5 * std::sqrt(expected * (1 - share))) << material;
  }
  const int neutral =
      drawn["car_white"] + drawn["car_black"] + drawn["car_grey"] + drawn["car_silver"];
  EXPECT_GT(neutral, 0.75 * kCars);
  // An object's shape seed picks its paint when the plan gives no material.
  std::set<std::string> paints;
  for (uint64_t seed = 0; seed < 40; ++seed)
    paints.insert(MakeClassShape("car", seed, "test").default_material);
  EXPECT_GE(paints.size(), 4u);
}

// A scene of 60 cars without an extent: each gets one shape's own size; the same seed gives the
// same sizes, another seed other ones, and every shape appears.
TEST(CarFamily, PlannedCarsGetTheirShapesOwnSizeDeterministicallyPerSeed) {
  const std::string scene =
      "LSCENE = ONE(W) MANY(V, 60)\nW = terrain{size:[300,300]}\n"
      "V = object{class:car,position:{ON:W}}\n";
  auto sizes_of = [&](uint64_t seed) {
    std::vector<size_t> shapes;
    for (const PlannedObject& o : testing::PlanText(scene, "", seed).objects) {
      if (o.class_name != "car") continue;
      size_t match = CarShapes().size();
      for (size_t i = 0; i < CarShapes().size(); ++i)
        if (o.extent == CarShapes()[i].size) match = i;
      EXPECT_LT(match, CarShapes().size()) << o.name << " " << o.extent.transpose();
      shapes.push_back(match);
    }
    return shapes;
  };
  const std::vector<size_t> a = sizes_of(7), b = sizes_of(7), c = sizes_of(8);
  ASSERT_EQ(a.size(), 60u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(std::set<size_t>(a.begin(), a.end()).size(), CarShapes().size());
}

}  // namespace
}  // namespace lsds::gen
