// The mesh-files plug-in: assimp's importer and glTF 2 exporter behind
// generator/scene/mesh_io_abi.h, the only code of the product that links assimp. Built as a CMake
// MODULE (docs/architecture.md, "Plug-ins"). It only copies between assimp's structures and the
// ABI's plain ones.
#include <algorithm>
#include <memory>

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>

#include "generator/scene/mesh_io_abi.h"

namespace lsds::gen {
namespace {

MeshFileMaterial MaterialOf(const aiScene& scene, const aiMaterial& material) {
  MeshFileMaterial out;
  aiString name;
  if (material.GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS &&
      material.GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS)
    return out;
  out.albedo_map = name.C_Str();
  if (out.albedo_map.empty()) return out;
  const aiTexture* embedded = scene.GetEmbeddedTexture(name.C_Str());
  if (embedded == nullptr) return out;
  out.embedded = true;
  out.width = embedded->mWidth;
  out.height = embedded->mHeight;
  if (embedded->mHeight == 0) {  // compressed (PNG, JPEG): mWidth bytes
    const auto* bytes = reinterpret_cast<const unsigned char*>(embedded->pcData);
    out.data.assign(bytes, bytes + embedded->mWidth);
    return out;
  }
  out.data.reserve(size_t{3} * embedded->mWidth * embedded->mHeight);
  for (size_t i = 0; i < size_t{embedded->mWidth} * embedded->mHeight; ++i) {
    const aiTexel& t = embedded->pcData[i];
    out.data.insert(out.data.end(), {t.r, t.g, t.b});
  }
  return out;
}

MeshFilePart PartOf(const aiMesh& in) {
  MeshFilePart out;
  out.material = in.mMaterialIndex;
  out.positions.reserve(size_t{3} * in.mNumVertices);
  for (unsigned v = 0; v < in.mNumVertices; ++v)
    out.positions.insert(out.positions.end(),
                         {in.mVertices[v].x, in.mVertices[v].y, in.mVertices[v].z});
  if (in.HasTextureCoords(0)) {
    out.uvs.reserve(size_t{2} * in.mNumVertices);
    for (unsigned v = 0; v < in.mNumVertices; ++v)
      out.uvs.insert(out.uvs.end(), {in.mTextureCoords[0][v].x, in.mTextureCoords[0][v].y});
  }
  for (unsigned f = 0; f < in.mNumFaces; ++f) {
    const aiFace& face = in.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines carry no surface
    out.triangles.insert(out.triangles.end(),
                         {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
  }
  return out;
}

bool Read(const std::string& path, MeshFile& file, std::string& error) {
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path,
                        aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                            aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr) {
    error = importer.GetErrorString();
    return false;
  }
  file = {};
  for (unsigned i = 0; i < scene->mNumMaterials; ++i)
    file.materials.push_back(MaterialOf(*scene, *scene->mMaterials[i]));
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) file.parts.push_back(PartOf(*scene->mMeshes[m]));
  return true;
}

aiVector3D Vector(const std::vector<float>& xyz, size_t i) {
  return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
}

aiMesh* MakeMesh(const GlbMesh& mesh) {
  const size_t vertices = mesh.positions.size() / 3, triangles = mesh.indices.size() / 3;
  const bool normals = !mesh.normals.empty();
  auto out = std::make_unique<aiMesh>();
  out->mName = aiString(mesh.name);
  out->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  out->mMaterialIndex = mesh.material;
  out->mNumVertices = static_cast<unsigned>(vertices);
  out->mVertices = new aiVector3D[vertices];
  if (normals) out->mNormals = new aiVector3D[vertices];
  const bool uvs = !mesh.uvs.empty();
  if (uvs) {
    out->mTextureCoords[0] = new aiVector3D[vertices];
    out->mNumUVComponents[0] = 2;
  }
  for (size_t i = 0; i < vertices; ++i) {
    out->mVertices[i] = Vector(mesh.positions, i);
    if (normals) out->mNormals[i] = Vector(mesh.normals, i);
    if (uvs) out->mTextureCoords[0][i] = aiVector3D(mesh.uvs[2 * i], mesh.uvs[2 * i + 1], 0.f);
  }
  out->mNumFaces = static_cast<unsigned>(triangles);
  out->mFaces = new aiFace[triangles];
  for (size_t t = 0; t < triangles; ++t) {
    aiFace& face = out->mFaces[t];
    face.mNumIndices = 3;
    face.mIndices =
        new unsigned[3]{mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]};
  }
  return out.release();
}

aiMaterial* MakeMaterial(const GlbMaterial& m) {
  auto out = std::make_unique<aiMaterial>();
  const aiString name(m.name);
  out->AddProperty(&name, AI_MATKEY_NAME);
  const aiColor4D color(m.base_color[0], m.base_color[1], m.base_color[2], 1.f);
  out->AddProperty(&color, 1, AI_MATKEY_BASE_COLOR);
  out->AddProperty(&color, 1, AI_MATKEY_COLOR_DIFFUSE);
  out->AddProperty(&m.roughness, 1, AI_MATKEY_ROUGHNESS_FACTOR);
  out->AddProperty(&m.metallic, 1, AI_MATKEY_METALLIC_FACTOR);
  return out.release();
}

bool WriteGlb(const std::vector<GlbMesh>& meshes,
              const std::vector<GlbMaterial>& materials,
              std::string& glb,
              std::string& error) {
  aiScene scene;  // owns (and deletes) everything attached below
  scene.mRootNode = new aiNode("lsds");
  scene.mNumMaterials = static_cast<unsigned>(materials.size());
  scene.mMaterials = new aiMaterial*[materials.size()];
  for (size_t i = 0; i < materials.size(); ++i) scene.mMaterials[i] = MakeMaterial(materials[i]);
  scene.mMeshes = new aiMesh*[std::max<size_t>(1, meshes.size())];
  scene.mRootNode->mChildren = new aiNode*[std::max<size_t>(1, meshes.size())];
  for (size_t first = 0; first < meshes.size();) {
    size_t end = first + 1;
    while (end < meshes.size() && meshes[end].name == meshes[first].name) ++end;
    auto* child = new aiNode(meshes[first].name);
    child->mParent = scene.mRootNode;
    child->mNumMeshes = static_cast<unsigned>(end - first);
    child->mMeshes = new unsigned[end - first];
    for (size_t m = first; m < end; ++m) {
      child->mMeshes[m - first] = scene.mNumMeshes;
      scene.mMeshes[scene.mNumMeshes++] = MakeMesh(meshes[m]);
    }
    scene.mRootNode->mChildren[scene.mRootNode->mNumChildren++] = child;
    first = end;
  }
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "glb2", 0);
  if (blob == nullptr) {
    error = exporter.GetErrorString();
    return false;
  }
  glb.assign(static_cast<const char*>(blob->data), blob->size);
  return true;
}

const MeshIoTable kTable = {kMeshIoAbiVersion, Read, WriteGlb};

}  // namespace
}  // namespace lsds::gen

extern "C" __attribute__((visibility("default"))) const lsds::gen::MeshIoTable*
lsds_mesh_io_table() {
  return &lsds::gen::kTable;
}
