// The object class factory: built-in procedural meshes in metres (cube, sphere,
// cylinder, cone, barrel, tire, jerrycan, rock, bush, person) and user meshes
// (OBJ, PLY, glTF, ... through assimp) named by file path. Unknown class names
// are rejected with a clear error.
#pragma once

#include <cstdint>
#include <map>
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

const std::vector<std::string>& BuiltinClassNames();  // canonical names
// Other spellings (plurals, `tyre`, `human`, ...) -> canonical name: one table.
const std::map<std::string, std::string>& ClassNameAliases();
// The canonical built-in class `name` spells, or "" when it names none.
std::string CanonicalClassName(const std::string& name);
bool IsMeshPath(const std::string& class_name);  // ends in a mesh file extension assimp reads

// The shape of `class_name`; `seed` varies the random classes (rock, bush).
// `where` names the plan object for error messages. Throws lsds::Error for
// unknown classes and unreadable meshes.
ClassShape MakeClassShape(const std::string& class_name, uint64_t seed, const std::string& where);

// Loads every mesh of a file with assimp (triangulated, node transforms
// applied, glTF's y-up turned to the world's z-up), in the file's units.
TriangleMesh LoadMeshFileNative(const std::string& path, const std::string& where);
// The same, normalized to the unit box (the renderer scales it by `extent`).
TriangleMesh LoadMeshFile(const std::string& path, const std::string& where);
// The size of the mesh's axis-aligned bounds in the file's units (z-up): the
// native extent an object drawn from the file gets.
Eigen::Vector3d MeshFileExtent(const std::string& path, const std::string& where);

}  // namespace lsds::gen
