#include "generator/lang/scene/class_catalog.h"

#include <cstdio>
#include <filesystem>

#include "generator/lang/asset_choice.h"
#include "generator/scene/mesh_formats.h"
#include "generator/scene/object_library.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// A built-in's other spelling (`rocks`) is the built-in (object_library.h).
std::string CanonicalBuiltin(const std::string& name) {
  const std::string canonical = gen::CanonicalClassName(name);
  return canonical.empty() ? name : canonical;
}

}  // namespace

ClassCatalog::ClassCatalog(const Program& scene)
    : scene_dir_(std::filesystem::path(scene.src->path).parent_path().generic_string()) {}

ClassCatalog ClassCatalog::OfCheckedScene(const Program& scene) {
  ClassCatalog assets(scene);
  for (const Definition& def : scene.definitions) {
    if (def.kind == "classes")
      for (const auto& [name, node] : def.body.Members()) assets.AddAlias(name, ReadString(node));
    if (def.kind == "asset_library") assets.SetLibrary(LoadSceneAssetLibrary(scene, def));
    if (def.kind == "blueprint") assets.AddBlueprint(def);
  }
  return assets;
}

std::vector<std::string> ClassCatalog::BuiltinNames() {
  std::vector<std::string> names;
  for (const auto& [name, extent] : BuiltinClasses()) names.push_back(name);
  return names;
}

SceneClass ClassCatalog::Resolve(const Node& where, const std::string& option) const {
  if (const auto alias = aliases_.find(option); alias != aliases_.end())
    return {CanonicalBuiltin(alias->second), option};
  if (BuiltinClasses().count(CanonicalBuiltin(option)))
    return {CanonicalBuiltin(option), CanonicalBuiltin(option)};
  if (gen::IsMeshPath(option)) {
    const std::string path =
        (std::filesystem::path(scene_dir_) / option).lexically_normal().generic_string();
    return {path, path};
  }
  std::vector<std::string> names = BuiltinNames();
  for (const auto& [alias, target] : aliases_) names.push_back(alias);
  where.Fail("unknown class '" + option + "'" + DidYouMean(option, names) +
             "; use a built-in class (" + Join(BuiltinNames(), ", ") + "), a mesh file (" +
             Join(gen::MeshExtensions(), " ") +
             ", relative to the scene file) or declare it in a classes{...} definition");
}

std::vector<SceneClass> ClassCatalog::Candidates(const Node& cls, const std::string& option) const {
  std::vector<SceneClass> out;
  for (const gen::LibraryAsset* a : SelectAssets(Library(), cls, option))
    out.push_back({a->file, AssetClassName(*a)});
  if (out.empty()) out.push_back(Resolve(cls, option));
  return out;
}

Eigen::Vector3d ClassCatalog::NaturalExtent(const std::string& asset,
                                            std::optional<double> metres_per_unit,
                                            const Node& where,
                                            const std::string& what,
                                            std::optional<uint64_t> member_key) {
  if (!gen::IsMeshPath(asset)) {
    const auto builtin = BuiltinClasses().find(asset);
    if (builtin != BuiltinClasses().end())
      return member_key ? gen::BuiltinNaturalExtent(asset, *member_key) : builtin->second;
  }
  auto cached = mesh_extents_.find(asset);
  if (cached == mesh_extents_.end()) {
    Eigen::Vector3d extent;
    try {
      extent = gen::MeshFileExtent(asset, what);
    } catch (const Error& e) {
      where.Fail(e.message() + " (" + asset + ")");
    }
    // A flat mesh (a plane) still needs a box: 1 mm thick.
    cached = mesh_extents_.emplace(asset, extent.cwiseMax(Eigen::Vector3d::Constant(1e-3))).first;
  }
  const Eigen::Vector3d& native = cached->second;
  if (!metres_per_unit && native.maxCoeff() > kLargestUndeclaredMeshM) {
    char size[96];
    std::snprintf(size, sizeof size, "%.4g x %.4g x %.4g", native.x(), native.y(), native.z());
    where.Fail(what + ": the mesh " + asset + " is " + size +
               " in its own units, which would be metres; give the unit it is modelled in "
               "(unit:cm, mm, in, ft, or unit:m if it really is that large)");
  }
  return native * metres_per_unit.value_or(1.0);
}

std::optional<double> ClassCatalog::LibraryMetresPerUnit(const std::string& asset) const {
  if (const gen::AssetLibrary* library = Library())
    for (const gen::LibraryAsset& a : library->assets())
      if (a.file == asset) return a.DeclaredMetresPerUnit();
  return std::nullopt;
}

std::optional<double> MetresPerUnit(const Definition& object) {
  const Node n = object.body.Find("unit");
  if (!n) return std::nullopt;
  static const std::map<std::string, double> kUnits = {
      {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}, {"ft", 0.3048}};
  const std::string unit = ReadString(n);
  const auto it = kUnits.find(unit);
  if (it == kUnits.end()) n.Fail("unit must be one of m, cm, mm, in, ft, not '" + unit + "'");
  return it->second;
}

}  // namespace lsds
