#include "generator/scene/world_ground.h"

#include <algorithm>
#include <cmath>

#include "generator/plan/terrain_height.h"
#include "generator/scene/smooth_normals.h"
#include "generator/scene/terrain.h"

namespace lsds::gen {

double GroundFadeWidth(const PlannedTerrain& terrain) {
  // About three hills wide, never more than half the terrain.
  const double period = 1.0 / std::max(1e-6, terrain.perlin_frequency);
  return std::max(1.0, std::min(3 * period, 0.5 * terrain.size.maxCoeff()));
}

double GroundSkirtReach(const PlannedTerrain& terrain) {
  return std::max(20000.0, 50 * terrain.size.maxCoeff());
}

double GroundHeight(const PlannedTerrain& terrain, double x, double y) {
  const double h = TerrainHeight(terrain, x, y);
  const double dx = std::max(0.0, std::abs(x) - 0.5 * terrain.size.x());
  const double dy = std::max(0.0, std::abs(y) - 0.5 * terrain.size.y());
  if (dx == 0 && dy == 0) return h;
  const double t = std::min(1.0, std::hypot(dx, dy) / GroundFadeWidth(terrain));
  const double w = 1 - t * t * (3 - 2 * t);  // smoothstep: no kink at the edge
  return kWorldGroundZ + w * (h - kWorldGroundZ);
}

TriangleMesh MakeGroundSkirt(const PlannedTerrain& terrain,
                             const TriangleMesh& terrain_mesh,
                             int max_cells) {
  const Eigen::Vector2i grid = TerrainGrid(terrain, max_cells);
  const int nx = grid.x(), ny = grid.y();
  // The terrain's boundary, counter-clockwise seen from above.
  std::vector<int> loop;
  loop.reserve(size_t{2} * (nx + ny));
  for (int i = 0; i < nx; ++i) loop.push_back(i);
  for (int j = 0; j < ny; ++j) loop.push_back(j * (nx + 1) + nx);
  for (int i = nx; i > 0; --i) loop.push_back(ny * (nx + 1) + i);
  for (int j = ny; j > 0; --j) loop.push_back(j * (nx + 1));
  const int n = static_cast<int>(loop.size());

  // Ring offsets past the edge: the terrain's own spacing (growing to a
  // quarter hill) while the hills fade, then doubling out to the reach.
  const double hx = 0.5 * terrain.size.x(), hy = 0.5 * terrain.size.y();
  const double reach = GroundSkirtReach(terrain);
  std::vector<double> rings = {0};
  if (terrain.perlin_amplitude != 0) {
    const double cell = std::min(2 * hx / nx, 2 * hy / ny);
    const double cap = std::max(cell, 0.25 / std::max(1e-6, terrain.perlin_frequency));
    const double fade = GroundFadeWidth(terrain);
    for (double step = cell; rings.back() < fade; step = std::min(step * 1.15, cap))
      rings.push_back(std::min(fade, rings.back() + step));
    while (rings.back() * 2 < reach) rings.push_back(rings.back() * 2);
  }
  rings.push_back(reach);

  TriangleMesh mesh;
  for (size_t r = 0; r < rings.size(); ++r) {
    const double ax = (hx + rings[r]) / hx, ay = (hy + rings[r]) / hy;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3f& edge = terrain_mesh.positions[loop[k]];
      if (r == 0) {
        mesh.positions.push_back(edge);  // shared exactly with the terrain
        continue;
      }
      const double x = edge.x() * ax, y = edge.y() * ay;
      mesh.positions.emplace_back(static_cast<float>(x),
                                  static_cast<float>(y),
                                  static_cast<float>(GroundHeight(terrain, x, y)));
    }
  }
  for (size_t r = 0; r + 1 < rings.size(); ++r) {
    const int inner = static_cast<int>(r) * n, outer = inner + n;
    for (int k = 0; k < n; ++k) {
      const int k1 = (k + 1) % n;
      mesh.triangles.emplace_back(inner + k, outer + k, outer + k1);
      mesh.triangles.emplace_back(inner + k, outer + k1, inner + k1);
    }
  }
  mesh.corner_normals = HeightfieldCornerNormals(
      mesh,
      [&terrain](double x, double y) { return GroundHeight(terrain, x, y); },
      TerrainNormalStep(terrain));
  return mesh;
}

}  // namespace lsds::gen
