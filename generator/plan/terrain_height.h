// The terrain surface shared by the planner (objects stand ON it) and the
// renderer (which meshes it): both must evaluate the very same function so that
// planned objects sit exactly on the rendered ground.
#pragma once

#include "generator/plan/plan.h"

namespace lsds {

// Height (world z, metres) of the terrain surface at (x, y):
//   amplitude * Perlin2(frequency * x, frequency * y; perlin_seed), Perlin2 in
//   [-1, 1] (Ken Perlin's 2002 improved noise restricted to 2D, permutation
//   shuffled from perlin_seed with SplitMix64).
// Zero everywhere when the terrain is absent or its amplitude is 0. Defined
// outside the terrain rectangle too (the renderer may skirt the edges).
double TerrainHeight(const PlannedTerrain& terrain, double x, double y);

// Perlin2 alone, for tests.
double PerlinNoise2(uint64_t seed, double x, double y);

}  // namespace lsds
