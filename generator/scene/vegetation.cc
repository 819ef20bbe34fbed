#include "generator/scene/vegetation.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "generator/plan/terrain_height.h"
#include "libs/util/counter_rng.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

// One blade: a bent strip of two quads (4 triangles) from a base 1.2 cm wide at the origin, out
// along +x by `lean` at the tip, up to `height`; narrowing to a point.
void AddBlade(TriangleMesh* mesh, float angle, float lean, float height) {
  const Eigen::Vector3f out(std::cos(angle), std::sin(angle), 0), side(-out.y(), out.x(), 0);
  const float w = 0.012f;
  const int base = static_cast<int>(mesh->positions.size());
  // Base pair, middle pair (half way up, a third of the lean), tip.
  mesh->positions.push_back(-0.5f * w * side);
  mesh->positions.push_back(0.5f * w * side);
  const Eigen::Vector3f middle = (lean / 3) * out + Eigen::Vector3f(0, 0, 0.55f * height);
  mesh->positions.push_back(middle - 0.4f * w * side);
  mesh->positions.push_back(middle + 0.4f * w * side);
  mesh->positions.push_back(lean * out + Eigen::Vector3f(0, 0, height));
  mesh->triangles.emplace_back(base, base + 1, base + 3);
  mesh->triangles.emplace_back(base, base + 3, base + 2);
  mesh->triangles.emplace_back(base + 2, base + 3, base + 4);
}

// A flat leaf: a diamond from `from` along `along` (length), `width` wide, in the plane of
// `along` and `side`.
void AddLeaf(TriangleMesh* mesh,
             const Eigen::Vector3f& from,
             const Eigen::Vector3f& along,
             const Eigen::Vector3f& side,
             float width) {
  const int base = static_cast<int>(mesh->positions.size());
  mesh->positions.push_back(from);
  mesh->positions.push_back(from + 0.45f * along - 0.5f * width * side);
  mesh->positions.push_back(from + along);
  mesh->positions.push_back(from + 0.45f * along + 0.5f * width * side);
  mesh->triangles.emplace_back(base, base + 1, base + 2);
  mesh->triangles.emplace_back(base, base + 2, base + 3);
}

}  // namespace

TriangleMesh PlantPrototype(const std::string& kind) {
  TriangleMesh mesh;
  if (kind == "grass") {
    // Nine blades round the tuft, leaning out by 0.1-0.35 of the height, the tallest reaching 1.
    for (int i = 0; i < 9; ++i) {
      const float angle =
          2.0f * static_cast<float>(M_PI) * (static_cast<float>(i) + 0.37f * (i % 3)) / 9;
      const float height = i == 0 ? 1.0f : 0.6f + 0.04f * static_cast<float>((i * 5) % 9);
      AddBlade(&mesh, angle, 0.1f + 0.03f * static_cast<float>((i * 7) % 9), height);
    }
  } else if (kind == "plants") {
    // Five leaves rising from the stem's foot, then a rosette of two crossed flat leaves whose
    // centre is the top (z = 1): what a nadir ray over the plant meets first.
    for (int i = 0; i < 5; ++i) {
      const float a = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / 5;
      const Eigen::Vector3f out(std::cos(a), std::sin(a), 0), side(-out.y(), out.x(), 0);
      AddLeaf(&mesh, {0, 0, 0.05f}, 0.45f * (out + Eigen::Vector3f(0, 0, 0.8f)), side, 0.14f);
    }
    for (const Eigen::Vector3f& along : {Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 1, 0)}) {
      const Eigen::Vector3f side(-along.y(), along.x(), 0);
      AddLeaf(&mesh, Eigen::Vector3f(0, 0, 1) - 0.22f * along, 0.44f * along, side, 0.16f);
    }
    TriangleMesh stem = MakeCylinderMesh(6);
    mesh.Append(stem, Eigen::Vector3f(0.02f, 0.02f, 0.98f).asDiagonal(), {0, 0, 0.49f});
  } else {
    throw Error("vegetation kind must be grass or plants, not '" + kind + "'");
  }
  return mesh;
}

size_t PlantCount(const PlannedTerrain& terrain) {
  const PlannedVegetation& v = terrain.vegetation;
  if (!terrain.present || !(v.density > 0)) return 0;
  const double cell = 1 / std::sqrt(v.density);
  return static_cast<size_t>(std::ceil(terrain.size.x() / cell)) *
         static_cast<size_t>(std::ceil(terrain.size.y() / cell));
}

std::vector<PlantInstance> ScatterVegetation(const PlannedTerrain& terrain) {
  std::vector<PlantInstance> plants;
  const PlannedVegetation& v = terrain.vegetation;
  const size_t cells = PlantCount(terrain);
  if (cells == 0) return plants;
  if (cells > kMaxPlants)
    throw Error("terrain vegetation: " + std::to_string(cells) + " plants (density " +
                std::to_string(v.density) + " per m^2 over the terrain) is over the limit of " +
                std::to_string(kMaxPlants) + "; lower the density or the terrain's size");
  const double cell = 1 / std::sqrt(v.density);
  const auto nx = static_cast<uint64_t>(std::ceil(terrain.size.x() / cell));
  const auto ny = static_cast<uint64_t>(std::ceil(terrain.size.y() / cell));
  const Eigen::Vector2d half = 0.5 * terrain.size;
  plants.reserve(cells);
  enum Draw : uint64_t { kX, kY, kTurn, kSize };
  for (uint64_t j = 0; j < ny; ++j) {
    for (uint64_t i = 0; i < nx; ++i) {
      const uint64_t c = j * nx + i;
      const double x = -half.x() + (static_cast<double>(i) + Uniform01(v.seed, c, 0, kX)) * cell;
      const double y = -half.y() + (static_cast<double>(j) + Uniform01(v.seed, c, 0, kY)) * cell;
      if (x > half.x() || y > half.y()) continue;
      const double turn = 2 * M_PI * Uniform01(v.seed, c, 0, kTurn);
      const double size = v.height_m * (0.7 + 0.6 * Uniform01(v.seed, c, 0, kSize));
      PlantInstance p;
      p.linear = (Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).matrix() * size).cast<float>();
      p.offset = Eigen::Vector3f(static_cast<float>(x),
                                 static_cast<float>(y),
                                 static_cast<float>(TerrainHeight(terrain, x, y)) - kPlantSinkM);
      plants.push_back(p);
    }
  }
  return plants;
}

TriangleMesh VegetationMesh(const PlannedTerrain& terrain) {
  TriangleMesh mesh;
  const std::vector<PlantInstance> plants = ScatterVegetation(terrain);
  if (plants.empty()) return mesh;
  const TriangleMesh prototype = PlantPrototype(terrain.vegetation.kind);
  mesh.positions.reserve(plants.size() * prototype.positions.size() + 1);  // + Embree's padding
  mesh.triangles.reserve(plants.size() * prototype.triangles.size());
  for (const PlantInstance& p : plants) mesh.Append(prototype, p.linear, p.offset);
  return mesh;
}

}  // namespace lsds::gen
