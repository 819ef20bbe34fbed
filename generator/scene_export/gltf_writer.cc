#include "generator/scene_export/gltf_writer.h"

#include <memory>
#include <utility>

#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/Exporter.hpp>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

// glTF's +Y-up frame from the world's +Z-up one.
aiVector3D GltfFromWorld(const Eigen::Vector3f& p) { return {p.x(), p.z(), -p.y()}; }

// One glTF mesh: the triangles as they are, with a vertex per distinct (position, normal) pair.
aiMesh* MakeMesh(const TriangleMesh& mesh, const std::string& name, int material) {
  const bool normals = mesh.corner_normals.size() == 3 * mesh.triangles.size();
  // Per source vertex, the glTF vertices made for it and their normals.
  std::vector<std::vector<std::pair<Eigen::Vector3f, unsigned>>> made(mesh.positions.size());
  std::vector<Eigen::Vector3f> positions, vertex_normals;
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
        vertex_normals.push_back(n);
        made[v].emplace_back(n, index);
      }
      indices.push_back(index);
    }
  }
  auto out = std::make_unique<aiMesh>();
  out->mName = aiString(name);
  out->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  out->mMaterialIndex = static_cast<unsigned>(material);
  out->mNumVertices = static_cast<unsigned>(positions.size());
  out->mVertices = new aiVector3D[positions.size()];
  if (normals) out->mNormals = new aiVector3D[positions.size()];
  for (size_t i = 0; i < positions.size(); ++i) {
    out->mVertices[i] = GltfFromWorld(positions[i]);
    if (normals) out->mNormals[i] = GltfFromWorld(vertex_normals[i]);
  }
  out->mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  out->mFaces = new aiFace[mesh.triangles.size()];
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    aiFace& face = out->mFaces[t];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3]{indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
  }
  return out.release();
}

aiMaterial* MakeMaterial(const GltfMaterial& m) {
  auto out = std::make_unique<aiMaterial>();
  const aiString name(m.name);
  out->AddProperty(&name, AI_MATKEY_NAME);
  const aiColor4D color(m.base_color.x(), m.base_color.y(), m.base_color.z(), 1.f);
  out->AddProperty(&color, 1, AI_MATKEY_BASE_COLOR);
  out->AddProperty(&color, 1, AI_MATKEY_COLOR_DIFFUSE);
  out->AddProperty(&m.roughness, 1, AI_MATKEY_ROUGHNESS_FACTOR);
  out->AddProperty(&m.metallic, 1, AI_MATKEY_METALLIC_FACTOR);
  return out.release();
}

}  // namespace

void WriteGlb(const std::filesystem::path& path,
              const std::vector<GltfNode>& nodes,
              const std::vector<GltfMaterial>& materials) {
  aiScene scene;  // owns (and deletes) everything attached below
  scene.mRootNode = new aiNode("lsds");
  std::vector<GltfMaterial> used = materials;
  if (used.empty()) used.push_back({});  // glTF meshes need a material
  scene.mNumMaterials = static_cast<unsigned>(used.size());
  scene.mMaterials = new aiMaterial*[used.size()];
  for (size_t i = 0; i < used.size(); ++i) scene.mMaterials[i] = MakeMaterial(used[i]);
  scene.mMeshes = new aiMesh*[std::max<size_t>(1, nodes.size())];
  scene.mRootNode->mChildren = new aiNode*[std::max<size_t>(1, nodes.size())];
  for (const GltfNode& node : nodes) {
    if (node.mesh == nullptr || node.mesh->triangles.empty()) continue;
    const unsigned index = scene.mNumMeshes;
    scene.mMeshes[index] = MakeMesh(*node.mesh, node.name, node.material);
    ++scene.mNumMeshes;
    auto* child = new aiNode(node.name);
    child->mParent = scene.mRootNode;
    child->mNumMeshes = 1;
    child->mMeshes = new unsigned[1]{index};
    scene.mRootNode->mChildren[scene.mRootNode->mNumChildren++] = child;
  }
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "glb2", 0);
  if (blob == nullptr)
    throw Error(std::string("glTF export failed: ") + exporter.GetErrorString(),
                Location(path.string()));
  WriteFileAtomic(path, std::string(static_cast<const char*>(blob->data), blob->size));
}

}  // namespace lsds::gen
