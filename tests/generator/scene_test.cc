// Scene entities: the class factory, materials, meshes, terrain, world state.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "generator/render/sky.h"
#include "generator/scene/materials.h"
#include "generator/scene/mesh_formats.h"
#include "generator/scene/object_library.h"
#include "generator/scene/perlin.h"
#include "generator/scene/terrain.h"
#include "generator/scene/world.h"
#include "libs/util/error.h"
#include "libs/util/splitmix64.h"
#include "tests/test_util.h"

namespace lsds::gen {
namespace {

TEST(ObjectLibrary, EveryBuiltinClassFillsTheUnitBox) {
  for (const std::string& name : BuiltinClassNames()) {
    const ClassShape shape = MakeClassShape(name, 3, "test");
    ASSERT_FALSE(shape.mesh.empty()) << name;
    Eigen::Vector3f lo = shape.mesh.positions[0], hi = lo;
    for (const Eigen::Vector3f& p : shape.mesh.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    EXPECT_TRUE(lo.isApprox(Eigen::Vector3f::Constant(-0.5f), 1e-5)) << name;
    EXPECT_TRUE(hi.isApprox(Eigen::Vector3f::Constant(0.5f), 1e-5)) << name;
    for (const Eigen::Vector3i& t : shape.mesh.triangles) {
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(t[k], 0);
        ASSERT_LT(t[k], static_cast<int>(shape.mesh.positions.size()));
      }
    }
    FindMaterial(shape.default_material, name);  // default materials exist
  }
}

TEST(ObjectLibrary, RandomClassesDependOnTheSeedOnly) {
  const ClassShape a = MakeClassShape("rock", 1, "t"), b = MakeClassShape("rock", 1, "t");
  const ClassShape c = MakeClassShape("rock", 2, "t");
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_NE(a.mesh.positions, c.mesh.positions);
}

TEST(ObjectLibrary, UnknownClassIsRejectedWithASuggestion) {
  try {
    MakeClassShape("barel", 0, "object 'O1#0'");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("unknown object class 'barel'"), std::string::npos) << message;
    EXPECT_NE(message.find("did you mean 'barrel'"), std::string::npos) << message;
    EXPECT_NE(message.find("O1#0"), std::string::npos) << message;
  }
  EXPECT_THROW(MakeClassShape("missing/file.obj", 0, "o"), Error);
}

TEST(ObjectLibrary, UserMeshesLoadThroughAssimpNormalized) {
  const lsds::testing::TempDir dir;
  const std::filesystem::path path = dir / "tetra.obj";
  {
    std::ofstream obj(path);
    obj << "v 0 0 0\nv 2 0 0\nv 0 4 0\nv 0 0 6\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 "
           "3 4\n";
  }
  ASSERT_TRUE(IsMeshPath(path.string()));
  const ClassShape shape = MakeClassShape(path.string(), 0, "object 'M#0'");
  EXPECT_EQ(shape.mesh.triangles.size(), 4u);
  Eigen::Vector3f lo = shape.mesh.positions[0], hi = lo;
  for (const Eigen::Vector3f& p : shape.mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3f::Constant(-0.5f), 1e-5));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f::Constant(0.5f), 1e-5));
  std::ofstream(path) << "this is not a mesh\n";
  EXPECT_THROW(MakeClassShape(path.string(), 0, "object 'M#0'"), Error);
}

TEST(Materials, UnknownNamesAreRejected) {
  EXPECT_THROW(FindMaterial("grasy", "terrain"), Error);
  EXPECT_EQ(FindMaterial("grassy", "terrain").name, "grassy");
  EXPECT_EQ(FindMaterial("MetalGold", "object").name,
            "metal_gold");  // case and '_' do not matter
}

TEST(Sky, UnknownCloudTypeIsRejected) {
  Plan plan;
  plan.sky.cloud_type = "cumulous";
  EXPECT_THROW(Sky{plan}, Error);
  plan.sky.cloud_type = "cirrus";
  plan.sky.cloud_density = 0.5;
  const Sky sky(plan);
  EXPECT_GT(sky.Radiance(Eigen::Vector3d(0, 0, 1)).sum(), 0);
  // The sun direction: azimuth from north (+y) clockwise, elevation above the
  // horizon.
  EXPECT_NEAR(sky.to_sun().norm(), 1, 1e-12);
  EXPECT_GT(sky.to_sun().x(), 0);  // default azimuth 135: south-east
  EXPECT_LT(sky.to_sun().y(), 0);
}

TEST(Perlin, IsDeterministicAndBounded) {
  const Perlin a(5), b(5), c(6);
  double differ = 0;
  for (int i = 0; i < 100; ++i) {
    const double x = i * 0.37, y = i * 0.11;
    EXPECT_EQ(a.Fbm(x, y, 4), b.Fbm(x, y, 4));
    EXPECT_LE(std::abs(a.Fbm(x, y, 4)), 1.5);
    differ += std::abs(a.Noise(x, y) - c.Noise(x, y));
  }
  EXPECT_GT(differ, 0);
}

// The slope bound the cloud shadow's exact reuse rests on
// (Sky::CloudTransmittance): central differences on a 1000 x 1000 grid of
// points for each of four seeds never exceed it.
TEST(Perlin, TheSlopeOfThe2DNoiseIsBounded) {
  double steepest = 0;
  for (const uint64_t seed : {1u, 2u, 3u, 4u}) {
    const Perlin noise(seed);
    const double h = 1e-6;
    for (int i = 0; i < 1000; ++i) {
      for (int j = 0; j < 1000; ++j) {
        const double x = i * 0.0641 + 0.013 + seed * 100, y = j * 0.0637 + 0.007;
        const double gx = (noise.Noise(x + h, y) - noise.Noise(x - h, y)) / (2 * h);
        const double gy = (noise.Noise(x, y + h) - noise.Noise(x, y - h)) / (2 * h);
        steepest = std::max(steepest, std::hypot(gx, gy));
      }
    }
  }
  EXPECT_LE(steepest, Perlin::kSlopeBound2D);
  EXPECT_GT(steepest, 2.5);  // the grid reaches the steep places
}

// "The same seed gives the same field on every machine": a digest of the
// noise's bits at 20000 points (negative, on lattice points, past the 256-cell
// period), pinned to the value of the portable x86-64 build before the AVX2
// clone (generator/scene/perlin.cc) existed. Whichever clone the CPU gets,
// and whatever flags a build adds, the field may not change.
TEST(Perlin, TheFieldIsTheSameOnEveryMachine) {
  const Perlin noise(HashString("machine"));
  uint64_t state = 3, digest = 0;
  auto mix = [&digest](double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    digest = HashCombine(digest, bits);
  };
  for (int i = 0; i < 20000; ++i) {
    double c[3];
    for (double& v : c) {
      const uint64_t r = SplitMix64Next(&state);
      const double unit = static_cast<double>(r >> 11) * 0x1p-53 * 2 - 1;
      v = r % 4 == 0 ? std::round(unit * 600) : unit * (r % 4 == 1 ? 3 : 2000);
    }
    mix(noise.Noise(c[0], c[1], c[2]));
    mix(noise.Noise(c[0], c[1]));
  }
  EXPECT_EQ(digest, 2868268950932652713ull);
}

// A smooth field may be evaluated once per pixel where it changes by less
// than an 8-bit step over the pixel (docs/generator.md, "Smooth fields once per
// pixel"). Over their reuse distances, in a random direction, the albedo of
// every material and the cloud shadow of every cloud type change by under
// 1/255 at 99.9 % of 20,000 random points and by under 3/255 anywhere.
struct Changes {
  double p999 = 0, max = 0;
  // The largest change where the reuse distance is past `exact_beyond`.
  double max_where_exact = 0;
};
template <typename Distance, typename Field>
Changes ChangesWithin(Distance distance_at,
                      Field field,
                      double exact_beyond = std::numeric_limits<double>::infinity()) {
  uint64_t state = 11;
  auto unit = [&state] { return static_cast<double>(SplitMix64Next(&state) >> 11) * 0x1p-53; };
  std::vector<double> changes;
  Changes c;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(unit() * 2000 - 1000, unit() * 2000 - 1000, unit() * 200 - 20);
    const double z = unit() * 2 - 1, a = unit() * 2 * M_PI, s = std::sqrt(1 - z * z);
    const Eigen::Vector3d u(s * std::cos(a), s * std::sin(a), z);
    const double distance = distance_at(p);
    changes.push_back(std::abs(field(p) - field(p + distance * u)));
    if (distance > exact_beyond) c.max_where_exact = std::max(c.max_where_exact, changes.back());
  }
  std::sort(changes.begin(), changes.end());
  c.p999 = changes[changes.size() * 999 / 1000];
  c.max = changes.back();
  return c;
}

TEST(Materials, TheAlbedoIsConstantWithinItsReuseDistance) {
  const Perlin noise(HashString("albedo"));
  for (const Material& m : MaterialTable()) {
    const double distance = AlbedoReuseDistance(m);
    if (m.contrast <= 0 && m.patches <= 0) {
      EXPECT_EQ(distance, std::numeric_limits<double>::infinity()) << m.name;
      continue;
    }
    if (m.pattern == Pattern::kSpeckle) {
      EXPECT_EQ(distance, 0) << m.name;  // hard-edged grains: per sample
      continue;
    }
    const Changes c =
        ChangesWithin([&](const Eigen::Vector3d&) { return distance; },
                      [&](const Eigen::Vector3d& p) {
                        return static_cast<double>(Albedo(m, noise, p.cast<float>()).maxCoeff());
                      });
    EXPECT_LT(c.p999, 1 / 255.0) << m.name;
    EXPECT_LT(c.max, 3 / 255.0) << m.name;
  }
}

// The cloud shadow's reuse distance is CloudReuseDistance() where the cover
// ramps, and farther where the deck is clear or full: there the value may not
// change at all.
TEST(Sky, TheCloudShadowIsConstantWithinItsReuseDistance) {
  for (const std::string& type : CloudTypes()) {
    for (const double elevation : {10.0, 45.0, 80.0}) {
      Plan plan;
      plan.sky.cloud_type = type;
      plan.sky.cloud_density = 0.5;
      plan.sun.elevation_deg = elevation;
      const Sky sky(plan);
      auto distance_at = [&](const Eigen::Vector3d& p) {
        double distance;
        sky.CloudTransmittance(p, &distance);
        return distance;
      };
      if (type == "none") {
        EXPECT_EQ(distance_at(Eigen::Vector3d(1, 2, 3)), std::numeric_limits<double>::infinity());
        continue;
      }
      auto field = [&](const Eigen::Vector3d& p) { return sky.CloudTransmittance(p); };
      const Changes ramp =
          ChangesWithin([&](const Eigen::Vector3d&) { return sky.CloudReuseDistance(); }, field);
      EXPECT_LT(ramp.p999, 1 / 255.0) << type << " " << elevation;
      EXPECT_LT(ramp.max, 3 / 255.0) << type << " " << elevation;
      const Changes c = ChangesWithin(distance_at, field, sky.CloudReuseDistance());
      EXPECT_LT(c.p999, 1 / 255.0) << type << " " << elevation;
      EXPECT_LT(c.max, 3 / 255.0) << type << " " << elevation;
      EXPECT_EQ(c.max_where_exact, 0) << type << " " << elevation;
      // Within the exact distance (which the renderer keeps across pixels,
      // ExactBall) nothing changes at all.
      auto exact_at = [&](const Eigen::Vector3d& p) {
        double reuse, exact;
        sky.CloudTransmittance(p, &reuse, &exact);
        return exact;
      };
      EXPECT_EQ(ChangesWithin(exact_at, field).max, 0) << type << " " << elevation;
      // Inside such a stretch: at least the ramp's distance, not past the deck.
      const Eigen::Vector3d low(3, 4, 5), near_deck(3, 4, 999.95);
      EXPECT_EQ(sky.CloudReuseDistanceInside(low, 0), sky.CloudReuseDistance());
      EXPECT_EQ(sky.CloudReuseDistanceInside(low, 7), std::max(7.0, sky.CloudReuseDistance()));
      EXPECT_NEAR(sky.CloudReuseDistanceInside(near_deck, 7), 0.05, 1e-9);
    }
  }
}

TEST(Terrain, FlatTerrainIsTwoTrianglesAtZeroAndHillsFollowTheHeight) {
  PlannedTerrain terrain;
  terrain.present = true;
  terrain.size = {100, 50};
  TriangleMesh flat = MakeTerrainMesh(terrain);
  EXPECT_EQ(flat.triangles.size(), 2u);
  for (const auto& p : flat.positions) EXPECT_EQ(p.z(), 0.f);
  terrain.perlin_amplitude = 4;
  terrain.perlin_frequency = 0.05;
  const TriangleMesh hills = MakeTerrainMesh(terrain);
  EXPECT_GT(hills.triangles.size(), 100u);
  for (const auto& p : hills.positions) {
    EXPECT_NEAR(p.z(), TerrainHeight(terrain, p.x(), p.y()), 1e-4);
  }
}

TEST(World, ChangesApplyToTheirFrameOnly) {
  Plan plan;
  PlannedObject o;
  o.name = "O1#0";
  o.class_name = "cube";
  plan.objects.push_back(o);
  PlannedFrame frame;
  ObjectChange change;
  change.object = "O1#0";
  change.position = Eigen::Vector3d(1, 2, 3);
  change.visible = false;
  frame.changes.push_back(change);
  const WorldState world = WorldAt(plan, frame);
  EXPECT_EQ(world.objects[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(world.objects[0].visible);
  EXPECT_EQ(WorldAt(plan, PlannedFrame{}).objects[0].position, Eigen::Vector3d::Zero());
  frame.changes[0].object = "nobody";
  EXPECT_THROW(WorldAt(plan, frame), Error);
}

}  // namespace
}  // namespace lsds::gen
