// The object class factory: built-in procedural meshes in metres (one table,
// BuiltinClassTable: primitives, barrel, tire, jerrycan, crate, rock, bush,
// tree, person, car, truck; builtin_meshes.h) and user meshes (OBJ, PLY,
// glTF, ... through assimp, with their base-colour textures) named by file
// path. Unknown class names are rejected with a clear error.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/scene/mesh.h"

namespace lsds::gen {

struct ClassShape {
  TriangleMesh mesh;             // normalized to the unit box of the object frame
  std::string default_material;  // when the plan leaves the material empty
  Eigen::Vector3d default_extent = Eigen::Vector3d::Ones();  // plausible size in metres
};

struct BuiltinClass {
  std::string name;                     // canonical
  Eigen::Vector3d default_extent;       // metres: the size an object gets when the plan gives none
  std::string default_material;         // when the plan leaves the material empty
  TriangleMesh (*make)(uint64_t seed);  // in metres; the seed varies rocks, bushes, trees, people
  // A family of shapes with their own proportions (car: builtin_meshes.h): the
  // size of the member a planner's draw `key` picks, and the mesh of the member
  // nearest an object's extent. Null for the other classes.
  Eigen::Vector3d (*member_extent)(uint64_t key) = nullptr;
  TriangleMesh (*make_for_extent)(const Eigen::Vector3d& extent) = nullptr;
  // A paint drawn per object from `seed` when the plan gives no material
  // (car); null: default_material.
  const std::string& (*paint)(uint64_t seed) = nullptr;
};
// The one home of the built-in classes (LSCENE's defaults read it too).
const std::vector<BuiltinClass>& BuiltinClassTable();
// The built-in class `name` (or an alias of it) spells; null when none.
const BuiltinClass* FindBuiltinClass(const std::string& name);
const std::vector<std::string>& BuiltinClassNames();  // canonical names, table order
// Other spellings (plurals, `tyre`, `human`, ...) -> canonical name: one table.
const std::map<std::string, std::string>& ClassNameAliases();
// The canonical built-in class `name` spells, or "" when it names none.
std::string CanonicalClassName(const std::string& name);

// The front of a built-in class as a unit direction of the object frame (the
// OBB's box frame), for the classes whose meshes have one: +x for car and
// truck (builtin_meshes.h), +y for person (the figure faces +y). nullopt for
// the symmetric classes and for mesh files, whose front nobody declared. The
// object truth puts its oriented boxes' heading corner there.
std::optional<Eigen::Vector3d> FrontOfBuiltinClass(const std::string& name);

// The natural size of built-in `name` (canonical or alias) drawn with planner key `key`: a
// family's member's own size (car), else the class's default_extent.
Eigen::Vector3d BuiltinNaturalExtent(const std::string& name, uint64_t key);

// The seed of an object's shape and paint: one per (plan seed, object name), so that an object
// keeps its look across frames and class swaps.
uint64_t ObjectShapeSeed(uint64_t plan_seed, const std::string& object_name);

// The shape of `class_name`; `seed` varies the random classes (rock, bush,
// tree, person) and the car's paint; `extent` (the object's planned size)
// picks a family's member (car: the shape nearest its proportions; without
// it, the family's first).
// `where` names the plan object for error messages. Throws lsds::Error for
// unknown classes and unreadable meshes.
ClassShape MakeClassShape(const std::string& class_name,
                          uint64_t seed,
                          const std::string& where,
                          const Eigen::Vector3d* extent = nullptr);

// Loads every mesh of a file with assimp (triangulated, node transforms
// applied, glTF's y-up turned to the world's z-up), in the file's units.
TriangleMesh LoadMeshFileNative(const std::string& path, const std::string& where);
// The same, normalized to the unit box (the renderer scales it by `extent`).
TriangleMesh LoadMeshFile(const std::string& path, const std::string& where);
// The size of the mesh's axis-aligned bounds in the file's units (z-up): the
// native extent an object drawn from the file gets.
Eigen::Vector3d MeshFileExtent(const std::string& path, const std::string& where);

}  // namespace lsds::gen
