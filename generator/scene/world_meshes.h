// The one home of the triangles a world state is drawn with, in world
// coordinates: the terrain and its skirt, and each rendered object's class
// shape placed by its state. The Embree scene (generator/render/embree_scene.h)
// casts exactly these triangles, and `lsds export-scene` writes exactly these
// (generator/scene_export/scene_export.h), so that another renderer draws the
// geometry lsds's truth was cast on.
#pragma once

#include "generator/plan/plan.h"
#include "generator/scene/mesh.h"
#include "generator/scene/object_library.h"
#include "generator/scene/world.h"

namespace lsds::gen {

// Object `state`'s shape in world coordinates: every vertex of the unit-box
// shape scaled by the extent, rotated and moved; smooth corner normals with
// sharp creases (CreaseCornerNormals), in world space.
TriangleMesh ObjectMeshInWorld(const ClassShape& shape, const ObjectState& state);

// The described terrain and the world ground's skirt around it
// (generator/scene/world_ground.h), sharing their boundary vertices.
struct GroundMeshes {
  TriangleMesh terrain, skirt;
};
GroundMeshes MakeGroundMeshes(const PlannedTerrain& terrain);

// The plane z = kWorldGroundZ past the skirt as triangles, for renderers that
// cannot intersect a plane: a rectangular ring from the skirt's outer edge out
// to `outer_scale` times its half size. The Embree scene intersects the plane
// itself; this is its export.
TriangleMesh MakeGroundPlaneRing(const PlannedTerrain& terrain, double outer_scale = 100);

}  // namespace lsds::gen
