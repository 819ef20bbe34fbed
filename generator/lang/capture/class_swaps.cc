#include "generator/lang/capture/class_swaps.h"

#include <algorithm>

#include "generator/lang/asset_choice.h"
#include "generator/scene/mesh_formats.h"
#include "generator/scene/object_library.h"
#include "libs/util/error.h"

namespace lsds {

std::vector<std::string> ClassSwaps::Options(const Node& cls) {
  if (IsTagSelection(cls)) return {"tags"};
  return StringOptions(cls);
}

std::vector<SceneClass> ClassSwaps::Candidates(const Node& cls, const std::string& option) {
  std::vector<SceneClass> out;
  for (const gen::LibraryAsset* a : SelectAssets(Library(), cls, option))
    out.push_back({a->file, AssetClassName(*a)});
  if (out.empty()) out.push_back(ResolveSceneClass(scene_, cls, option));
  return out;
}

const gen::AssetLibrary* ClassSwaps::Library() {
  if (!library_loaded_) {
    library_loaded_ = true;
    for (const Definition& d : scene_.definitions)
      if (d.kind == "asset_library") library_ = LoadSceneAssetLibrary(scene_, d);
  }
  return library_ ? &*library_ : nullptr;
}

std::pair<std::string, uint32_t> ClassSwaps::Class(const std::string& symbol,
                                                   const SceneClass& resolved) {
  const auto label = labels_.find(symbol);
  if (label != labels_.end() && label->second != 0) return {resolved.asset, label->second};
  uint32_t next = 1;
  for (const ClassInfo& c : plan_->classes) {
    if (c.name == resolved.name) return {resolved.asset, c.id};
    next = std::max(next, c.id + 1);
  }
  for (const auto& [s, l] : labels_) next = std::max(next, l + 1);
  plan_->classes.push_back({next, resolved.name});
  return {resolved.asset, next};
}

Eigen::Vector3d ClassSwaps::NaturalExtent(const SceneClass& drawn, const Node& where) {
  double metres_per_unit = 1.0;
  if (const gen::AssetLibrary* library = Library())
    for (const gen::LibraryAsset& a : library->assets())
      if (a.file == drawn.asset) metres_per_unit = a.metres_per_unit;
  if (!gen::IsMeshPath(drawn.asset)) {
    const auto builtin = BuiltinClasses().find(drawn.asset);
    if (builtin != BuiltinClasses().end()) return builtin->second;
  }
  auto cached = mesh_extents_.find(drawn.asset);
  if (cached == mesh_extents_.end()) {
    Eigen::Vector3d extent;
    try {
      extent = gen::MeshFileExtent(drawn.asset, "class change");
    } catch (const Error& e) {
      where.Fail(e.message() + " (" + drawn.asset + ")");
    }
    // A flat mesh (a plane) still needs a box: 1 mm thick, as LSCENE places it.
    cached =
        mesh_extents_.emplace(drawn.asset, extent.cwiseMax(Eigen::Vector3d::Constant(1e-3))).first;
  }
  return cached->second * metres_per_unit;
}

void ClassSwaps::Declare(const std::string& symbol, const Node& cls) {
  for (const std::string& option : Options(cls))
    for (const SceneClass& candidate : Candidates(cls, option))
      swapped_in_.insert(Class(symbol, candidate).second);
}

}  // namespace lsds
