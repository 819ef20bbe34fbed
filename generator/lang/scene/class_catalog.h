// What a class option of a scene names (docs/languages.md, "Class names"): a classes{} alias, a
// built-in class, a mesh file relative to the scene, or assets of the scene's asset library; and
// the natural size of what it draws. One home for LSCENE objects and LCAP class swaps.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/lang/scene.h"
#include "generator/scene/asset_library.h"

namespace lsds {

class ClassCatalog {
 public:
  // Knows the scene's folder only; the scene check adds the aliases and the library as it meets
  // them (scene/scene_check.h).
  explicit ClassCatalog(const Program& scene);
  // The assets of a checked scene: its classes{} aliases and asset_library, read without checks.
  static ClassCatalog OfCheckedScene(const Program& scene);

  void AddAlias(const std::string& name, const std::string& target) { aliases_[name] = target; }
  void AddBlueprint(const Definition& blueprint) { blueprints_[blueprint.symbol] = &blueprint; }
  // The blueprint `name` names (scene/blueprints.h), or null.
  const Definition* Blueprint(const std::string& name) const {
    const auto it = blueprints_.find(name);
    return it == blueprints_.end() ? nullptr : it->second;
  }
  void SetLibrary(gen::AssetLibrary library) { library_ = std::move(library); }
  bool HasLibrary() const { return library_.has_value(); }
  const gen::AssetLibrary* Library() const { return library_ ? &*library_ : nullptr; }

  // The asset class option `option` draws (a built-in's canonical name or a mesh path relative to
  // the scene file) and the class name it is labelled with (an alias keeps the user's name). An
  // unknown option is an error at `where`.
  SceneClass Resolve(const Node& where, const std::string& option) const;

  // What option `option` of class node `cls` may draw: the library assets it selects (by name,
  // tags or pattern), else the one class it resolves to.
  std::vector<SceneClass> Candidates(const Node& cls, const std::string& option) const;

  // The size an asset has of its own, metres: a built-in's box, a mesh's native bounds times
  // `metres_per_unit` (a mesh file is read once; a flat mesh is 1 mm thick). A mesh that cannot
  // be read is an error at `where`, `what` naming the object or change. A mesh whose unit nobody
  // declared (nullopt: read as metres) over kLargestUndeclaredMeshM on a side is an error asking
  // for its unit: a model in centimetres would otherwise become a 300 m pipe.
  // A built-in family (car) draws its member's own size from `member_key` (Rng::KeyHere); without
  // it, the class's default size.
  Eigen::Vector3d NaturalExtent(const std::string& asset,
                                std::optional<double> metres_per_unit,
                                const Node& where,
                                const std::string& what,
                                std::optional<uint64_t> member_key = std::nullopt);
  // The purpose of Rng::KeyHere keys that draw a family's member.
  static constexpr uint64_t kMemberKeyPurpose = 0x6d656d626572;  // "member"
  static constexpr double kLargestUndeclaredMeshM = 100;
  // The unit a library manifest declares for an asset's file; nullopt when none does.
  std::optional<double> LibraryMetresPerUnit(const std::string& asset) const;

  static std::vector<std::string> BuiltinNames();

 private:
  std::string scene_dir_;
  std::map<std::string, std::string> aliases_;  // classes{}: name -> built-in or mesh file
  std::map<std::string, const Definition*> blueprints_;
  std::optional<gen::AssetLibrary> library_;
  std::map<std::string, Eigen::Vector3d> mesh_extents_;  // native units, by file path
};

// An object's `unit` (the unit its mesh file is modelled in): metres per unit; nullopt without one.
std::optional<double> MetresPerUnit(const Definition& object);

}  // namespace lsds
