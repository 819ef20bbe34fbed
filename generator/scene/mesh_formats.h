// The mesh files a class or an asset may name: which extensions are meshes and
// which axis convention a format implies. One list for LSCENE, the asset
// library and the mesh loader.
#pragma once

#include <string>
#include <vector>

namespace lsds::gen {

// The extensions assimp reads for us: lower case, with the dot. Matched
// case-insensitively: `Rock.OBJ` is a mesh.
const std::vector<std::string>& MeshExtensions();
bool IsMeshPath(const std::string& path);

// A mesh file's up axis when nothing else says: glTF is y-up by its
// specification; the other formats carry none and are taken as z-up.
bool IsYUpByFormat(const std::string& path);

}  // namespace lsds::gen
