#include "generator/scene/terrain.h"

#include <algorithm>
#include <cmath>

#include "generator/scene/smooth_normals.h"
#include "generator/scene/world_ground.h"

namespace lsds::gen {

Eigen::Vector2i TerrainGrid(const PlannedTerrain& terrain, int max_cells) {
  int nx = 1, ny = 1;
  if (terrain.perlin_amplitude != 0) {
    // About four vertices per noise period on the finest octave we show,
    // bounded.
    const double spacing = std::max(0.25, 0.125 / std::max(1e-6, terrain.perlin_frequency));
    nx = std::clamp(static_cast<int>(std::ceil(terrain.size.x() / spacing)), 1, max_cells);
    ny = std::clamp(static_cast<int>(std::ceil(terrain.size.y() / spacing)), 1, max_cells);
  }
  return {nx, ny};
}

double TerrainNormalStep(const PlannedTerrain& terrain) {
  return 1e-3 / std::max(1e-6, terrain.perlin_frequency);
}

TriangleMesh MakeTerrainMesh(const PlannedTerrain& terrain, int max_cells) {
  TriangleMesh mesh;
  const double sx = terrain.size.x(), sy = terrain.size.y();
  const Eigen::Vector2i grid = TerrainGrid(terrain, max_cells);
  const int nx = grid.x(), ny = grid.y();
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = -sx / 2 + sx * i / nx, y = -sy / 2 + sy * j / ny;
      mesh.positions.emplace_back(static_cast<float>(x),
                                  static_cast<float>(y),
                                  static_cast<float>(TerrainHeight(terrain, x, y)));
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      mesh.triangles.emplace_back(a, b, d);
      mesh.triangles.emplace_back(a, d, c);
    }
  }
  // Shading normals of the true surface, not of the facets.
  mesh.corner_normals = HeightfieldCornerNormals(
      mesh,
      [&terrain](double x, double y) { return GroundHeight(terrain, x, y); },
      TerrainNormalStep(terrain));
  return mesh;
}

}  // namespace lsds::gen
