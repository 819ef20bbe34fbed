#include "generator/scene/object_library.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "generator/scene/asset_library.h"
#include "generator/scene/perlin.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

// Displaces every vertex of a unit sphere along its radius by fractal noise:
// rocks and bush lobes.
void DisplaceRadially(TriangleMesh* mesh, uint64_t seed, double amplitude, double frequency) {
  const Perlin noise(seed);
  for (Eigen::Vector3f& p : mesh->positions) {
    const double n =
        noise.Fbm(p.x() * frequency + 11.3, p.y() * frequency + 7.1, p.z() * frequency + 3.7, 4);
    p *= static_cast<float>(1 + amplitude * n);
  }
}

TriangleMesh Rock(uint64_t seed) {
  TriangleMesh mesh = MakeSphereMesh(24, 12);
  DisplaceRadially(&mesh, seed, 0.45, 2.0);
  for (Eigen::Vector3f& p : mesh.positions) p.z() *= 0.6f;  // rocks are flatter than tall
  return mesh;
}

TriangleMesh Bush(uint64_t seed) {
  TriangleMesh mesh;
  uint64_t state = seed;
  auto uniform = [&state]() {
    state = HashCombine(state, 0x5bd1e995);
    return static_cast<double>(state >> 11) / static_cast<double>(uint64_t{1} << 53);
  };
  const int lobes = 5 + static_cast<int>(uniform() * 4);
  for (int i = 0; i < lobes; ++i) {
    TriangleMesh lobe = MakeSphereMesh(12, 6);
    DisplaceRadially(&lobe, HashCombine(seed, i), 0.25, 3.0);
    const float r = static_cast<float>(0.5 + 0.4 * uniform());
    const double a = 2 * M_PI * uniform();
    const float d = static_cast<float>(0.45 * uniform());
    const Eigen::Vector3f offset(d * static_cast<float>(std::cos(a)),
                                 d * static_cast<float>(std::sin(a)),
                                 static_cast<float>(0.5 * uniform() * r));
    mesh.Append(lobe, Eigen::Matrix3f::Identity() * r, offset);
  }
  return mesh;
}

TriangleMesh Jerrycan() {
  TriangleMesh mesh;
  const TriangleMesh box = MakeBoxMesh();
  mesh.Append(box, Eigen::Vector3f(0.17f, 0.35f, 0.45f).asDiagonal(), Eigen::Vector3f(0, 0, 0));
  // Handle bar on top and a spout at one corner.
  mesh.Append(
      box, Eigen::Vector3f(0.05f, 0.2f, 0.04f).asDiagonal(), Eigen::Vector3f(0, -0.03f, 0.245f));
  mesh.Append(MakeCylinderMesh(12),
              Eigen::Vector3f(0.05f, 0.05f, 0.06f).asDiagonal(),
              Eigen::Vector3f(0, 0.13f, 0.25f));
  return mesh;
}

TriangleMesh Tire() {
  // A torus standing on its tread: axis along the object's y.
  TriangleMesh torus = MakeTorusMesh(32, 12, 0.45);
  Eigen::Matrix3f z_to_y;
  z_to_y << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  TriangleMesh mesh;
  mesh.Append(torus, z_to_y);
  return mesh;
}

TriangleMesh Person() {
  // A capsule: a cylinder with hemispherical ends (radius 0.5 of the normalized
  // width).
  return MakeLatheMesh(16, 16, [](double t) {
    const double cap = 0.18;  // share of the height taken by each hemisphere
    if (t < cap) return 0.5 * std::sqrt(std::max(0.0, 1 - std::pow((cap - t) / cap, 2)));
    if (t > 1 - cap) return 0.5 * std::sqrt(std::max(0.0, 1 - std::pow((t - 1 + cap) / cap, 2)));
    return 0.5;
  });
}

}  // namespace

const std::vector<std::string>& BuiltinClassNames() {
  static const std::vector<std::string> names = {"cube",
                                                 "sphere",
                                                 "cylinder",
                                                 "cone",
                                                 "barrel",
                                                 "tire",
                                                 "jerrycan",
                                                 "watercan",
                                                 "rock",
                                                 "bush",
                                                 "person"};
  return names;
}

// The one table of other spellings: plurals (the paper writes `rocks`),
// British spellings and synonyms. Each resolves to the same class, so both
// spellings share one class id and one shape.
const std::map<std::string, std::string>& ClassNameAliases() {
  static const std::map<std::string, std::string> aliases = {
      {"cubes", "cube"},        {"box", "cube"},           {"boxes", "cube"},
      {"spheres", "sphere"},    {"cylinders", "cylinder"}, {"cones", "cone"},
      {"barrels", "barrel"},    {"tires", "tire"},         {"tyre", "tire"},
      {"tyres", "tire"},        {"jerrycans", "jerrycan"}, {"watercans", "watercan"},
      {"rocks", "rock"},        {"bushes", "bush"},        {"persons", "person"},
      {"people", "person"},     {"human", "person"},       {"humans", "person"},
      {"pedestrian", "person"}, {"pedestrians", "person"}};
  return aliases;
}

std::string CanonicalClassName(const std::string& name) {
  const auto alias = ClassNameAliases().find(name);
  if (alias != ClassNameAliases().end()) return alias->second;
  const auto& names = BuiltinClassNames();
  return std::find(names.begin(), names.end(), name) != names.end() ? name : std::string();
}

bool IsMeshPath(const std::string& class_name) {
  std::string ext = std::filesystem::path(class_name).extension().string();
  std::transform(
      ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const std::vector<std::string> known = {
      ".obj", ".ply", ".gltf", ".glb", ".fbx", ".stl", ".dae", ".3ds", ".off"};
  return std::find(known.begin(), known.end(), ext) != known.end();
}

TriangleMesh LoadMeshFileNative(const std::string& path, const std::string& where) {
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(where + ": mesh file not found", Location(path));
  }
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path,
                        aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                            aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr) {
    throw Error(where + ": cannot read mesh: " + importer.GetErrorString(), Location(path));
  }
  // glTF is y-up by its specification; the world is z-up: (x, y, z) ->
  // (x, -z, y). Other formats carry no axis convention and are taken as z-up,
  // unless an asset library's manifest lists the file with its own up axis.
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(
      ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  const std::optional<LibraryAsset> listed = LibraryAssetOf(path);
  const bool y_up = listed ? listed->y_up : ext == ".gltf" || ext == ".glb";
  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    const int base = static_cast<int>(mesh.positions.size());
    for (unsigned v = 0; v < in->mNumVertices; ++v) {
      const aiVector3D& p = in->mVertices[v];
      if (y_up)
        mesh.positions.emplace_back(p.x, -p.z, p.y);
      else
        mesh.positions.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      mesh.triangles.emplace_back(
          base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
    }
  }
  if (mesh.empty()) throw Error(where + ": the mesh file has no triangles", Location(path));
  return mesh;
}

TriangleMesh LoadMeshFile(const std::string& path, const std::string& where) {
  TriangleMesh mesh = LoadMeshFileNative(path, where);
  NormalizeToUnitBox(&mesh);
  return mesh;
}

Eigen::Vector3d MeshFileExtent(const std::string& path, const std::string& where) {
  const TriangleMesh mesh = LoadMeshFileNative(path, where);
  Eigen::Vector3f lo = mesh.positions.front(), hi = lo;
  for (const Eigen::Vector3f& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).cast<double>();
}

ClassShape MakeClassShape(const std::string& name, uint64_t seed, const std::string& where) {
  ClassShape shape;
  const std::string canonical = CanonicalClassName(name);
  if (!canonical.empty() && canonical != name) return MakeClassShape(canonical, seed, where);
  if (name == "cube") {
    shape = {MakeBoxMesh(), "concrete", {1, 1, 1}};
  } else if (name == "sphere") {
    shape = {MakeSphereMesh(32, 16), "white", {1, 1, 1}};
  } else if (name == "cylinder") {
    shape = {MakeCylinderMesh(32), "metal", {0.6, 0.6, 1.2}};
  } else if (name == "cone") {
    shape = {MakeConeMesh(32), "orange", {0.4, 0.4, 0.7}};
  } else if (name == "barrel") {
    shape = {MakeLatheMesh(24, 8, [](double t) { return 0.44 + 0.06 * std::sin(M_PI * t); }),
             "painted_blue",
             {0.6, 0.6, 0.9}};
  } else if (name == "tire") {
    shape = {Tire(), "rubber", {0.65, 0.22, 0.65}};
  } else if (name == "jerrycan" || name == "watercan") {
    shape = {Jerrycan(), name == "jerrycan" ? "painted_green" : "painted_blue", {0.17, 0.35, 0.47}};
  } else if (name == "rock") {
    shape = {Rock(seed), "stone", {1.0, 0.8, 0.5}};
  } else if (name == "bush") {
    shape = {Bush(seed), "foliage", {1.5, 1.5, 1.2}};
  } else if (name == "person") {
    shape = {Person(), "fabric", {0.45, 0.3, 1.75}};
  } else if (IsMeshPath(name)) {
    shape = {LoadMeshFile(name, where), "plastic", {1, 1, 1}};
    return shape;
  } else {
    throw Error(where + ": unknown object class '" + name + "'" +
                DidYouMean(name, BuiltinClassNames()) +
                "; built-in classes: " + Join(BuiltinClassNames(), ", ") +
                ", or a mesh file path (.obj, .ply, .gltf, .glb, ...)");
  }
  NormalizeToUnitBox(&shape.mesh);
  return shape;
}

}  // namespace lsds::gen
