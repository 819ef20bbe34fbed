// The terrain: a heightfield mesh over [-size/2, size/2]^2 from Perlin noise. A flat terrain
// (amplitude 0) is two triangles at z = 0 exactly, so analytic tests see an exact plane.
#pragma once

#include "generator/plan/plan.h"
#include "generator/scene/mesh.h"

namespace lsds::gen {

// Height of the terrain at a world (x, y) point.
double TerrainHeight(const PlannedTerrain& terrain, double x, double y);
// The mesh in world coordinates; `max_cells` bounds the grid resolution per axis.
TriangleMesh MakeTerrainMesh(const PlannedTerrain& terrain, int max_cells = 256);

}  // namespace lsds::gen
