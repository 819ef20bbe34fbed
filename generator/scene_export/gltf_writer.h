// Binary glTF 2.0 (.glb) of world-space triangle meshes, written through
// assimp's glTF 2 exporter: one node per mesh, one metallic-roughness material
// per entry. glTF is +Y up: a world point (x, y, z) (+Z up, ENU) is stored as
// (x, z, -y), which every importer that converts to +Z up (Blender's does by
// default) turns back into world coordinates exactly (docs/export.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/scene/mesh.h"

namespace lsds::gen {

struct GltfMaterial {
  std::string name;
  Eigen::Vector3f base_color = Eigen::Vector3f::Constant(0.5f);  // linear
  float roughness = 1.f;
  float metallic = 0.f;
};

// One glTF primitive: consecutive entries of the same name are one node's primitives (a mesh
// whose parts have different materials).
struct GltfNode {
  std::string name;
  const TriangleMesh* mesh = nullptr;  // world coordinates; corner normals and uvs optional
  int material = 0;                    // index into the materials
};

// Writes `nodes` atomically to `path`. Vertices are split only where a
// vertex's corners have different shading normals, so the triangles are the
// mesh's exactly. Throws lsds::Error naming the file when assimp fails.
void WriteGlb(const std::filesystem::path& path,
              const std::vector<GltfNode>& nodes,
              const std::vector<GltfMaterial>& materials);

}  // namespace lsds::gen
