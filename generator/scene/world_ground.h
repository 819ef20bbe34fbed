// The world beyond the described terrain (docs/generator.md, "An unbounded
// world"): the ground continues to the horizon so that no camera sees a void
// past the terrain's edge. Its hills fade out over a short distance into the
// plane z = 0, which a ring mesh (the "skirt") carries out to a large radius;
// past it the renderer intersects the plane itself. The world ground is
// background: class 0, instance 0, no truth object; it has a finite depth,
// normal and world position like any surface.
#pragma once

#include "generator/plan/plan.h"
#include "generator/scene/mesh.h"

namespace lsds::gen {

// The height of the plane the world ground settles to, past the fade.
constexpr double kWorldGroundZ = 0.0;

// The ground's height anywhere: the terrain's (lsds::TerrainHeight) inside its
// rectangle, blended to kWorldGroundZ over GroundFadeWidth outside it.
double GroundHeight(const PlannedTerrain& terrain, double x, double y);
// How far past the terrain's edge its hills fade out, metres.
double GroundFadeWidth(const PlannedTerrain& terrain);
// How far past the terrain's edge the skirt mesh reaches, metres.
double GroundSkirtReach(const PlannedTerrain& terrain);

// Rings of quads from the terrain mesh's boundary (bit-identical vertices, no
// crack) out to GroundSkirtReach, with smooth corner normals. `terrain_mesh` is
// MakeTerrainMesh(terrain, max_cells).
TriangleMesh MakeGroundSkirt(const PlannedTerrain& terrain,
                             const TriangleMesh& terrain_mesh,
                             int max_cells = 256);

}  // namespace lsds::gen
