// The terrain surface shared by the planner (objects stand ON it) and the
// renderer (which meshes it): both must evaluate the very same function so that
// planned objects sit exactly on the rendered ground.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "generator/plan/plan.h"

namespace lsds {

// Height (world z, metres) of the terrain surface at (x, y):
//   amplitude * Perlin2(frequency * x, frequency * y; perlin_seed), Perlin2 in
//   [-1, 1] (Ken Perlin's 2002 improved noise restricted to 2D, permutation
//   shuffled from perlin_seed with SplitMix64).
// Zero everywhere when the terrain is absent or its amplitude is 0. Defined
// outside the terrain rectangle too (the renderer may skirt the edges).
double TerrainHeight(const PlannedTerrain& terrain, double x, double y);

// Where the ray origin + t * direction (t > 0) first meets the terrain surface
// within `max_range` (along a unit `direction`), or nothing. Flat terrain is
// intersected exactly; hills by marching in steps no longer than a tenth of a
// Perlin wavelength and refining by bisection to 1 mm.
std::optional<Eigen::Vector3d> IntersectTerrain(const PlannedTerrain& terrain,
                                                const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& direction,
                                                double max_range);

// Perlin2 alone, for tests.
double PerlinNoise2(uint64_t seed, double x, double y);

}  // namespace lsds
