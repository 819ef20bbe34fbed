#include "generator/scene/mesh_formats.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace lsds::gen {
namespace {

std::string LowerCaseExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(
      ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

const std::vector<std::string>& MeshExtensions() {
  static const std::vector<std::string> known = {
      ".obj", ".ply", ".gltf", ".glb", ".fbx", ".stl", ".dae", ".3ds", ".off"};
  return known;
}

bool IsMeshPath(const std::string& path) {
  const std::string ext = LowerCaseExtension(path);
  return std::find(MeshExtensions().begin(), MeshExtensions().end(), ext) != MeshExtensions().end();
}

bool IsYUpByFormat(const std::string& path) {
  const std::string ext = LowerCaseExtension(path);
  return ext == ".gltf" || ext == ".glb";
}

}  // namespace lsds::gen
