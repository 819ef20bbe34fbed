// The terrain: a heightfield mesh over [-size/2, size/2]^2 from Perlin noise. A
// flat terrain (amplitude 0) is two triangles at z = 0 exactly, so analytic
// tests see an exact plane.
#pragma once

#include "generator/plan/plan.h"
#include "generator/plan/terrain_height.h"
#include "generator/scene/mesh.h"

namespace lsds::gen {

// Heights come from lsds::TerrainHeight (generator/plan/terrain_height.h), the
// very function the planner uses to stand objects ON the terrain. The mesh in
// world coordinates; `max_cells` bounds the grid resolution per axis. Its
// corner normals are the smooth surface's (central differences of the height).
TriangleMesh MakeTerrainMesh(const PlannedTerrain& terrain, int max_cells = 256);
// The mesh's cells along x and y.
Eigen::Vector2i TerrainGrid(const PlannedTerrain& terrain, int max_cells = 256);
// The central-difference step of the terrain's shading normals, metres.
double TerrainNormalStep(const PlannedTerrain& terrain);

}  // namespace lsds::gen
