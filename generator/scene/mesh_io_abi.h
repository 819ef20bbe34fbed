// The boundary between lsds and its mesh-files plug-in (generator/scene/mesh_io_plugin.cc), the
// only code that links assimp (and through it draco and minizip): reading the mesh files a class
// or an asset names (object_library.h) and writing the binary glTF of `lsds export-scene`
// (generator/scene_export/gltf_writer.h). The plug-in only moves data between assimp's structures
// and the plain ones below; what lsds makes of them (axes, textures, normals) stays in lsds. One
// extern "C" entry point returns a table of function pointers; both sides are built in one tree
// with the same libstdc++, so std::string and std::vector cross by reference.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lsds::gen {

// Raised whenever the table's layout or meaning changes; the loader refuses any other value.
constexpr int kMeshIoAbiVersion = 2;

// One material of a mesh file: its base-colour map (glTF's baseColorTexture, else the diffuse
// map, OBJ's map_Kd), as assimp names it.
struct MeshFileMaterial {
  std::string albedo_map;  // the texture's name; empty when the material has none
  // When the name is a texture embedded in the file ("*0"): assimp's aiTexture. Height 0: a
  // compressed image (PNG, JPEG) of `width` bytes in `data`; otherwise width x height texels,
  // 3 bytes (R, G, B) each in `data`.
  bool embedded = false;
  uint32_t width = 0, height = 0;
  std::vector<unsigned char> data;
};

// One mesh of the file (assimp's aiMesh after triangulation and pre-transformed vertices).
struct MeshFilePart {
  uint32_t material = 0;            // index into the materials, as the file gives it
  std::vector<float> positions;     // x, y, z per vertex, in the file's frame and units
  std::vector<float> uvs;           // u, v per vertex (texture coordinate set 0); empty: none
  std::vector<uint32_t> triangles;  // 3 vertex indices per triangle; other faces left out
};

struct MeshFile {
  std::vector<MeshFileMaterial> materials;
  std::vector<MeshFilePart> parts;
};

// One glTF primitive, in glTF's frame. Consecutive meshes of the same name are one node (one
// glTF mesh whose primitives they are, in order).
struct GlbMesh {
  std::string name;
  uint32_t material = 0;
  std::vector<float> positions;   // x, y, z per vertex
  std::vector<float> normals;     // x, y, z per vertex; empty: none
  std::vector<float> uvs;         // u, v per vertex (TEXCOORD_0), v up as assimp's; empty: none
  std::vector<uint32_t> indices;  // 3 per triangle
};

// One glTF metallic-roughness material.
struct GlbMaterial {
  std::string name;
  float base_color[3] = {0.5f, 0.5f, 0.5f};  // linear
  float roughness = 1.f;
  float metallic = 0.f;
};

struct MeshIoTable {
  int abi_version;
  // Reads `path` with assimp (triangulated, identical vertices joined, node transforms applied,
  // sorted by primitive type) into `file`; false with assimp's message in `error` when it cannot.
  bool (*read)(const std::string& path, MeshFile& file, std::string& error);
  // The .glb bytes of `meshes` (a node per run of same-named meshes, under a root node "lsds")
  // with `materials` (at least one), from assimp's glTF 2 exporter, which makes a node's meshes
  // the primitives of one glTF mesh; false with its message in `error`.
  bool (*write_glb)(const std::vector<GlbMesh>& meshes,
                    const std::vector<GlbMaterial>& materials,
                    std::string& glb,
                    std::string& error);
};

constexpr const char* kMeshIoPlugin = "lsds_mesh_io.so";
constexpr const char* kMeshIoEntry = "lsds_mesh_io_table";

// The plug-in's table, opened on first use (libs/util/plugin.h); throws lsds::Error when it
// cannot be loaded.
const MeshIoTable& MeshIo();

}  // namespace lsds::gen

// Defined by the plug-in; looked up with dlsym by kMeshIoEntry.
extern "C" const lsds::gen::MeshIoTable* lsds_mesh_io_table();
