#include "generator/scene/object_library.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include "generator/scene/asset_library.h"
#include "generator/scene/builtin_meshes.h"
#include "generator/scene/mesh_formats.h"
#include "generator/scene/mesh_io_abi.h"
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

// The base-colour map of a mesh file's material: glTF's baseColorTexture or
// the diffuse map (OBJ's map_Kd), a file next to the mesh or embedded in it
// ("*0"); null when it has none. The colour factors are not applied: the map
// is the albedo (docs/generator.md, "Image textures").
std::shared_ptr<const ImageTexture> AlbedoMapOf(const MeshFileMaterial& material,
                                                const std::string& mesh_path,
                                                const std::string& where) {
  const std::string& file = material.albedo_map;
  if (file.empty()) return nullptr;
  const std::string context = where + ": mesh '" + mesh_path + "'";
  if (material.embedded) {
    if (material.height == 0)  // compressed (PNG, JPEG): width bytes
      return DecodeImageTexture(material.data.data(), material.width, context);
    return MakeImageTexture(
        static_cast<int>(material.width), static_cast<int>(material.height), material.data.data());
  }
  const std::filesystem::path image = std::filesystem::path(mesh_path).parent_path() / file;
  if (!std::filesystem::is_regular_file(image))
    throw Error(context + ": texture image '" + file + "' not found", Location(image.string()));
  return LoadImageTexture(image.string(), context);
}

}  // namespace

// The one table of built-in classes: each class's default size (what an
// object gets when the plan gives no extent; LSCENE reads it from here),
// default material and mesh. Sizes are the meshes' own proportions, so the
// default draws them undistorted.
const std::vector<BuiltinClass>& BuiltinClassTable() {
  using V = Eigen::Vector3d;
  static const std::vector<BuiltinClass> table = {
      {"cube", V(1, 1, 1), "concrete", [](uint64_t) { return MakeBoxMesh(); }},
      {"sphere", V(1, 1, 1), "white", [](uint64_t) { return MakeSphereMesh(32, 16); }},
      {"cylinder", V(1, 1, 1), "metal", [](uint64_t) { return MakeCylinderMesh(32); }},
      {"cone", V(1, 1, 1), "orange", [](uint64_t) { return MakeConeMesh(32); }},
      {"barrel", V(0.6, 0.6, 0.9), "painted_blue", [](uint64_t) { return BarrelMesh(); }},
      {"tire", V(0.7, 0.25, 0.7), "rubber", [](uint64_t) { return Tire(); }},
      {"jerrycan", V(0.17, 0.35, 0.47), "painted_green", [](uint64_t) { return Jerrycan(); }},
      {"watercan", V(0.17, 0.35, 0.47), "painted_blue", [](uint64_t) { return Jerrycan(); }},
      {"crate", V(1.0, 0.8, 0.8), "wood", [](uint64_t) { return CrateMesh(); }},
      {"rock", V(1.0, 0.8, 0.6), "stone", RockMesh},
      {"bush", V(1.2, 1.2, 1.0), "foliage", Bush},
      {"tree", V(4.5, 4.5, 7.0), "foliage", TreeMesh},
      {"person", V(0.5, 0.3, 1.8), "fabric", HumanMesh},
      {"car",
       CarShapes().front().size,
       "car_white",
       [](uint64_t) { return CarMesh(0); },
       [](uint64_t key) { return CarShapes()[CarShapeOfKey(key)].size; },
       [](const Eigen::Vector3d& extent) { return CarMesh(CarShapeNearest(extent)); },
       CarPaint},
      {"truck", V(8.0, 2.5, 3.2), "painted", [](uint64_t) { return TruckMesh(); }},
  };
  return table;
}

const BuiltinClass* FindBuiltinClass(const std::string& name) {
  const std::string canonical = CanonicalClassName(name);
  for (const BuiltinClass& c : BuiltinClassTable())
    if (c.name == canonical) return &c;
  return nullptr;
}

const std::vector<std::string>& BuiltinClassNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const BuiltinClass& c : BuiltinClassTable()) out.push_back(c.name);
    return out;
  }();
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
      {"pedestrian", "person"}, {"pedestrians", "person"}, {"crates", "crate"},
      {"trees", "tree"},        {"cars", "car"},           {"automobile", "car"},
      {"automobiles", "car"},   {"trucks", "truck"},       {"lorry", "truck"},
      {"lorries", "truck"}};
  return aliases;
}

std::string CanonicalClassName(const std::string& name) {
  const auto alias = ClassNameAliases().find(name);
  if (alias != ClassNameAliases().end()) return alias->second;
  const auto& names = BuiltinClassNames();
  return std::find(names.begin(), names.end(), name) != names.end() ? name : std::string();
}

std::optional<Eigen::Vector3d> FrontOfBuiltinClass(const std::string& name) {
  const std::string canonical = CanonicalClassName(name);
  if (canonical == "car" || canonical == "truck") return Eigen::Vector3d::UnitX();
  if (canonical == "person") return Eigen::Vector3d::UnitY();
  return std::nullopt;
}

TriangleMesh LoadMeshFileNative(const std::string& path, const std::string& where) {
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(where + ": mesh file not found", Location(path));
  }
  MeshFile file;
  std::string error;
  if (!MeshIo().read(path, file, error))
    throw Error(where + ": cannot read mesh: " + error, Location(path));
  // A y-up file turns into the z-up world: (x, y, z) -> (x, -z, y). An asset
  // library's manifest may give a file its own up axis.
  const std::optional<LibraryAsset> listed = LibraryAssetOf(path);
  const bool y_up = listed ? listed->y_up : IsYUpByFormat(path);
  TriangleMesh mesh;
  // The base-colour map of each material (-1: none), read once.
  std::vector<int> material_map(file.materials.size(), -1);
  for (size_t i = 0; i < file.materials.size(); ++i) {
    if (auto map = AlbedoMapOf(file.materials[i], path, where)) {
      material_map[i] = static_cast<int>(mesh.albedo_maps.size());
      mesh.albedo_maps.push_back(std::move(map));
    }
  }
  const bool textured = !mesh.albedo_maps.empty();
  for (const MeshFilePart& in : file.parts) {
    const int base = static_cast<int>(mesh.positions.size());
    const int map =
        in.material < material_map.size() && !in.uvs.empty() ? material_map[in.material] : -1;
    for (size_t v = 0; 3 * v < in.positions.size(); ++v) {
      const float x = in.positions[3 * v], y = in.positions[3 * v + 1], z = in.positions[3 * v + 2];
      if (y_up)
        mesh.positions.emplace_back(x, -z, y);
      else
        mesh.positions.emplace_back(x, y, z);
      if (textured) {
        if (map >= 0)
          mesh.uvs.emplace_back(in.uvs[2 * v], in.uvs[2 * v + 1]);
        else
          mesh.uvs.emplace_back(0.f, 0.f);
      }
    }
    for (size_t t = 0; 3 * t < in.triangles.size(); ++t) {
      mesh.triangles.emplace_back(base + static_cast<int>(in.triangles[3 * t]),
                                  base + static_cast<int>(in.triangles[3 * t + 1]),
                                  base + static_cast<int>(in.triangles[3 * t + 2]));
      if (textured) mesh.triangle_map.push_back(map);
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

Eigen::Vector3d BuiltinNaturalExtent(const std::string& name, uint64_t key) {
  const BuiltinClass* builtin = FindBuiltinClass(name);
  if (builtin == nullptr) throw Error("internal: '" + name + "' is no built-in class");
  return builtin->member_extent ? builtin->member_extent(key) : builtin->default_extent;
}

uint64_t ObjectShapeSeed(uint64_t plan_seed, const std::string& object_name) {
  return HashCombine(plan_seed, HashString(object_name.c_str()));
}

ClassShape MakeClassShape(const std::string& name,
                          uint64_t seed,
                          const std::string& where,
                          const Eigen::Vector3d* extent) {
  ClassShape shape;
  if (const BuiltinClass* builtin = FindBuiltinClass(name)) {
    shape = {extent && builtin->make_for_extent ? builtin->make_for_extent(*extent)
                                                : builtin->make(seed),
             builtin->paint ? builtin->paint(seed) : builtin->default_material,
             builtin->default_extent};
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
