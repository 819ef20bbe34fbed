// The image textures of loaded assets in `lsds export-scene` (docs/export.md, "Textures"): an
// object whose mesh has base-colour maps (generator/scene/mesh.h, albedo_maps) is exported as
// one primitive per albedo, each map written once into the export's textures/ folder, so that
// other renderers give its triangles the albedo the reference renderer samples.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "generator/scene/mesh.h"

namespace lsds::gen {

// The triangles of a mesh that share one albedo, and the record that says which
// (docs/export.md, a node's `parts`): {} the material's own albedo, {"albedo": [r, g, b]} a
// one-texel map's linear colour, {"albedo_map": "textures/..."} an image.
struct AlbedoPart {
  TriangleMesh mesh;  // the whole mesh's vertices, the part's triangles and corner normals
  nlohmann::json record;
  bool constant = false;  // a one-texel map: `colour` is its albedo
  Eigen::Vector3f colour = Eigen::Vector3f::Ones();
};

// Writes each distinct map of the meshes it splits once, into `folder`/textures/.
class TextureExporter {
 public:
  explicit TextureExporter(std::filesystem::path folder) : folder_(std::move(folder)) {}

  // The mesh's parts, one per distinct albedo in the order of the first map index that has it
  // (-1, the material's albedo, first); empty when the mesh has no maps (export it whole).
  std::vector<AlbedoPart> Split(const TriangleMesh& mesh);

 private:
  // The map's file, relative to the export folder; written on first use.
  std::string FileOf(const ImageTexture& map);

  std::filesystem::path folder_;
  std::map<const ImageTexture*, std::string> files_;
};

}  // namespace lsds::gen
