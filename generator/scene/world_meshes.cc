#include "generator/scene/world_meshes.h"

#include "generator/scene/smooth_normals.h"
#include "generator/scene/terrain.h"
#include "generator/scene/world_ground.h"

namespace lsds::gen {

TriangleMesh ObjectMeshInWorld(const ClassShape& shape, const ObjectState& state) {
  TriangleMesh mesh = shape.mesh;
  const Eigen::Matrix3f linear =
      (state.world_from_object * state.extent.asDiagonal()).cast<float>();
  const Eigen::Vector3f offset = state.position.cast<float>();
  for (Eigen::Vector3f& p : mesh.positions) p = linear * p + offset;
  mesh.corner_normals = CreaseCornerNormals(mesh);  // smooth shading, sharp creases
  return mesh;
}

GroundMeshes MakeGroundMeshes(const PlannedTerrain& terrain) {
  GroundMeshes ground;
  ground.terrain = MakeTerrainMesh(terrain);
  ground.skirt = MakeGroundSkirt(terrain, ground.terrain);
  return ground;
}

TriangleMesh MakeGroundPlaneRing(const PlannedTerrain& terrain, double outer_scale) {
  // The skirt's outer ring is the terrain's boundary scaled by (h + reach) / h per axis: a
  // rectangle of these half sizes.
  const double reach = GroundSkirtReach(terrain);
  const double ix = 0.5 * terrain.size.x() + reach, iy = 0.5 * terrain.size.y() + reach;
  const auto z = static_cast<float>(kWorldGroundZ);
  TriangleMesh ring;
  // Inner corners 0-3 and outer corners 4-7, counter-clockwise seen from above.
  for (const double s : {1.0, outer_scale}) {
    const auto x = static_cast<float>(s * ix), y = static_cast<float>(s * iy);
    ring.positions.insert(ring.positions.end(), {{-x, -y, z}, {x, -y, z}, {x, y, z}, {-x, y, z}});
  }
  for (int k = 0; k < 4; ++k) {
    const int k1 = (k + 1) % 4;
    ring.triangles.emplace_back(k, 4 + k, 4 + k1);  // up-facing, as the skirt's
    ring.triangles.emplace_back(k, 4 + k1, k1);
  }
  ring.corner_normals.assign(ring.triangles.size() * 3, Eigen::Vector3f::UnitZ());
  return ring;
}

}  // namespace lsds::gen
