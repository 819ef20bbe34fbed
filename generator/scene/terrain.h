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
// world coordinates; `max_cells` bounds the grid resolution per axis.
TriangleMesh MakeTerrainMesh(const PlannedTerrain& terrain, int max_cells = 256);

}  // namespace lsds::gen
