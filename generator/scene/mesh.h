// Triangle meshes and the procedural primitives the built-in object classes are
// made of. Every class mesh is normalized to the unit box [-0.5, 0.5]^3 of its
// object frame (z up), so that an object's `extent` scales it to exactly the
// size the plan asks for and its OBB is tight.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "generator/scene/texture.h"

namespace lsds::gen {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside
  // Optional shading normals, three per triangle (one per corner, so that a
  // crease keeps its edge without splitting vertices: the ray-tracing geometry,
  // and with it every truth layer, is the same with or without them). Empty:
  // flat shading. Filled in world space (terrain, RenderScene); Append drops
  // them.
  std::vector<Eigen::Vector3f> corner_normals;
  // Optional image textures (loaded assets): texture coordinates, one per
  // vertex (empty: none), and per triangle the index of its base-colour map
  // in `albedo_maps` (-1: the material's procedural albedo). Shading only.
  std::vector<Eigen::Vector2f> uvs;
  std::vector<int> triangle_map;
  std::vector<std::shared_ptr<const ImageTexture>> albedo_maps;

  void Append(const TriangleMesh& other,
              const Eigen::Matrix3f& linear = Eigen::Matrix3f::Identity(),
              const Eigen::Vector3f& offset = Eigen::Vector3f::Zero());
  bool empty() const { return triangles.empty(); }
};

TriangleMesh MakeBoxMesh();  // [-0.5, 0.5]^3
// A surface of revolution about z: `radius(t)` for t in [0, 1] from z = -0.5 to
// z = 0.5, closed by caps where the radius is not zero.
TriangleMesh MakeLatheMesh(int segments, int rings, double (*radius)(double t));
TriangleMesh MakeSphereMesh(int segments, int rings);  // radius 0.5
TriangleMesh MakeCylinderMesh(int segments);           // radius 0.5, height 1
TriangleMesh MakeConeMesh(int segments);               // base radius 0.5 at z = -0.5
// An icosahedron subdivided `subdivisions` times, vertices on the sphere of
// radius 0.5: evenly spread vertices (no poles), for irregular rocks.
TriangleMesh MakeIcosphereMesh(int subdivisions);
TriangleMesh MakeTorusMesh(int segments, int sides,
                           double minor_over_major);  // axis z

// Scales and centres the mesh so that its bounding box is exactly [-0.5, 0.5]^3
// (flat axes stay 0).
void NormalizeToUnitBox(TriangleMesh* mesh);

}  // namespace lsds::gen
