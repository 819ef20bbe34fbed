#include "generator/scene_export/gltf_writer.h"

#include <utility>

#include "generator/scene/mesh_io_abi.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

// glTF's +Y-up frame from the world's +Z-up one, appended to `xyz`.
void AppendGltfFromWorld(const Eigen::Vector3f& p, std::vector<float>* xyz) {
  xyz->insert(xyz->end(), {p.x(), p.z(), -p.y()});
}

// One glTF primitive: the triangles as they are, with a vertex per distinct (position, normal)
// pair, and the mesh's texture coordinates when it has them.
GlbMesh MakeMesh(const TriangleMesh& mesh, const std::string& name, int material) {
  const bool normals = mesh.corner_normals.size() == 3 * mesh.triangles.size();
  // Per source vertex, the glTF vertices made for it and their normals.
  std::vector<std::vector<std::pair<Eigen::Vector3f, unsigned>>> made(mesh.positions.size());
  std::vector<Eigen::Vector3f> positions, vertex_normals;
  std::vector<int> source_vertex;  // per glTF vertex
  std::vector<unsigned> indices;
  indices.reserve(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles[t][c];
      const Eigen::Vector3f n = normals ? mesh.corner_normals[3 * t + c] : Eigen::Vector3f::Zero();
      unsigned index = 0;
      bool found = false;
      for (const auto& [normal, i] : made[v]) {
        if (normal == n) {
          index = i;
          found = true;
          break;
        }
      }
      if (!found) {
        index = static_cast<unsigned>(positions.size());
        positions.push_back(mesh.positions[v]);
        source_vertex.push_back(v);
        vertex_normals.push_back(n);
        made[v].emplace_back(n, index);
      }
      indices.push_back(index);
    }
  }
  GlbMesh out;
  out.name = name;
  out.material = static_cast<uint32_t>(material);
  out.positions.reserve(3 * positions.size());
  if (normals) out.normals.reserve(3 * positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    AppendGltfFromWorld(positions[i], &out.positions);
    if (normals) AppendGltfFromWorld(vertex_normals[i], &out.normals);
  }
  if (mesh.uvs.size() == mesh.positions.size()) {
    out.uvs.reserve(2 * positions.size());
    for (const int v : source_vertex)
      out.uvs.insert(out.uvs.end(), {mesh.uvs[v].x(), mesh.uvs[v].y()});
  }
  out.indices = std::move(indices);
  return out;
}

}  // namespace

void WriteGlb(const std::filesystem::path& path,
              const std::vector<GltfNode>& nodes,
              const std::vector<GltfMaterial>& materials) {
  std::vector<GlbMaterial> used;
  used.reserve(materials.size());
  for (const GltfMaterial& m : materials) {
    used.push_back(
        {m.name, {m.base_color.x(), m.base_color.y(), m.base_color.z()}, m.roughness, m.metallic});
  }
  if (used.empty()) used.emplace_back();  // glTF meshes need a material
  std::vector<GlbMesh> meshes;
  for (const GltfNode& node : nodes) {
    if (node.mesh == nullptr || node.mesh->triangles.empty()) continue;
    meshes.push_back(MakeMesh(*node.mesh, node.name, node.material));
  }
  std::string glb, error;
  if (!MeshIo().write_glb(meshes, used, glb, error))
    throw Error("glTF export failed: " + error, Location(path.string()));
  WriteFileAtomic(path, glb);
}

}  // namespace lsds::gen
