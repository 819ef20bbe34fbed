#include "generator/render/embree_scene.h"

#include "generator/render/embree_abi.h"
#include "generator/scene/perlin.h"
#include "generator/scene/vegetation.h"
#include "generator/scene/world_meshes.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

// Embree reports through a C callback: remember the message, CheckDevice()
// throws it from C++.
thread_local std::string last_error;
void ErrorFunction(void*, RTCError, const char* message) {
  last_error = message ? message : "unknown error";
}

void CheckDevice(RTCDevice device) {
  if (Embree().get_device_error(device) != RTC_ERROR_NONE) throw Error("Embree: " + last_error);
}

}  // namespace

EmbreeDevice::EmbreeDevice() {
  device_ = Embree().new_device(nullptr);
  if (device_ == nullptr) throw Error("cannot create the Embree device");
  Embree().set_device_error_function(device_, ErrorFunction, nullptr);
}

EmbreeDevice::~EmbreeDevice() { Embree().release_device(device_); }

const ClassShape& SceneAssets::ShapeOf(size_t i, const std::string& asset) const {
  const auto swap = swapped.find({i, asset});
  return swap == swapped.end() ? shapes[i] : swap->second;
}

double RenderSceneBytes(const SceneAssets& assets) {
  constexpr double kBytesPerTriangle = 280;
  double triangles = 0;
  for (const ClassShape& shape : assets.shapes)
    triangles += static_cast<double>(shape.mesh.triangles.size());
  for (const auto& [key, shape] : assets.swapped)
    triangles += static_cast<double>(shape.mesh.triangles.size());
  triangles += static_cast<double>(assets.vegetation_triangles);
  return kBytesPerTriangle * triangles;
}

SceneAssets BuildSceneAssets(const Plan& plan) {
  SceneAssets assets;
  assets.shapes.reserve(plan.objects.size());
  for (const PlannedObject& o : plan.objects) {
    const std::string where = "object '" + o.name + "'";
    assets.shapes.push_back(
        MakeClassShape(o.class_name, ObjectShapeSeed(plan.seed, o.name), where, &o.extent));
    FindMaterial(o.material.empty() ? assets.shapes.back().default_material : o.material, where);
  }
  if (plan.terrain.present)
    assets.terrain_material = &FindMaterial(plan.terrain.material, "terrain");
  if (plan.terrain.present && PlantCount(plan.terrain) > 0)
    assets.vegetation_triangles =
        PlantCount(plan.terrain) * PlantPrototype(plan.terrain.vegetation.kind).triangles.size();
  for (const PlannedFrame& f : plan.frames) {
    if (f.environment && plan.terrain.present)  // fail before rendering
      FindMaterial(f.environment->terrain_material,
                   "frame " + std::to_string(f.index) + " terrain");
    for (const ObjectChange& c : f.changes) {
      if (c.asset) {
        size_t i = 0;
        while (i < plan.objects.size() && plan.objects[i].name != c.object) ++i;
        if (i == plan.objects.size())
          throw Error("frame " + std::to_string(f.index) + ": a change refers to unknown object '" +
                      c.object + "'");
        const PlannedObject& o = plan.objects[i];
        if (*c.asset != o.class_name && !assets.swapped.count({i, *c.asset}))
          assets.swapped.emplace(
              std::make_pair(i, *c.asset),
              MakeClassShape(*c.asset,
                             ObjectShapeSeed(plan.seed, o.name),
                             "frame " + std::to_string(f.index) + " object '" + c.object + "'",
                             c.extent ? &*c.extent : nullptr));
      }
      if (c.material)
        FindMaterial(*c.material,
                     "frame " + std::to_string(f.index) + " object '" + c.object + "'");
    }
  }
  return assets;
}

std::optional<Eigen::Vector3f> Surface::MappedAlbedo(unsigned prim, float u, float v) const {
  if (mesh == nullptr || prim >= mesh->triangle_map.size() || mesh->uvs.empty())
    return std::nullopt;
  const int map = mesh->triangle_map[prim];
  if (map < 0) return std::nullopt;
  const Eigen::Vector3i& t = mesh->triangles[prim];
  const Eigen::Vector2f uv =
      (1 - u - v) * mesh->uvs[t[0]] + u * mesh->uvs[t[1]] + v * mesh->uvs[t[2]];
  return mesh->albedo_maps[map]->Sample(uv);
}

RenderScene::RenderScene(const EmbreeDevice& device,
                         const Plan& plan,
                         const SceneAssets& assets,
                         const WorldState& world,
                         const RenderScene* earlier)
    : world_(world) {
  scene_ = Embree().new_scene(device.get());
  // Two levels: a BVH per geometry, kept while the geometry stays attached,
  // under a BVH over them, so that Update() rebuilds only what changed (one
  // moving object: 0.4 ms instead of 12-15 ms for the demo's 60 objects).
  // Embree builds these per geometry BVHs at low quality; the demo's rays
  // trace as fast as through one high-quality BVH over every triangle
  // (docs/generator.md "Performance").
  Embree().set_scene_flags(scene_, RTC_SCENE_FLAG_DYNAMIC);
  Embree().set_scene_build_quality(scene_, RTC_BUILD_QUALITY_LOW);
  first_object_id_ = plan.terrain.present ? 2 : 0;
  const size_t ids = first_object_id_ + world.objects.size();
  geometries_.assign(ids, nullptr);
  meshes_.resize(ids);
  surfaces_.resize(ids);
  object_scenes_.assign(world.objects.size(), nullptr);
  if (plan.terrain.present) {
    BuildGround(device, world);
    ground_plane_ = static_cast<int>(ids);  // after every Embree geometry id
    surfaces_.push_back(surfaces_[1]);      // the skirt's: background
    surfaces_.back().positions = nullptr;
    surfaces_.back().triangles = nullptr;
    surfaces_.back().corner_normals = nullptr;
    surfaces_.back().mesh = nullptr;
    SetTerrainMaterial(assets, world);
    BuildVegetation(device, world);
  }
  for (size_t i = 0; i < world.objects.size(); ++i)
    PlaceObject(device, assets, i, world.objects[i], earlier);
  Embree().commit_scene(scene_);
  CheckDevice(device.get());
}

void RenderScene::Update(const EmbreeDevice& device,
                         const SceneAssets& assets,
                         const WorldState& world,
                         const RenderScene* earlier) {
  if (world.objects.size() != world_.objects.size())
    throw Error("internal: a scene can only be updated to a world state of its plan");
  if (ground_plane_ >= 0 && !world_.SameGround(world)) {
    // A terrain shape change (LCAP, at a shot's start): the ground is meshed again.
    for (const unsigned id : {0U, 1U}) {
      Embree().detach_geometry(scene_, id);
      Embree().release_geometry(geometries_[id]);
      geometries_[id] = nullptr;
      meshes_[id].reset();
    }
    BuildGround(device, world);
    RemoveVegetation();
    BuildVegetation(device, world);
  }
  if (ground_plane_ >= 0) SetTerrainMaterial(assets, world);
  for (size_t i = 0; i < world.objects.size(); ++i) {
    const ObjectState& o = world.objects[i];
    if (world_.objects[i] == o) continue;  // its geometry and BVH as they are
    RemoveObject(i);
    PlaceObject(device, assets, i, o, earlier);
  }
  world_ = world;
  Embree().commit_scene(scene_);
  CheckDevice(device.get());
}

void RenderScene::BuildGround(const EmbreeDevice& device, const WorldState& world) {
  Surface s;
  s.class_id = world.terrain.class_id;
  s.instance_id = world.terrain.instance_id;
  // The unbounded world: background ground of the same material past the
  // terrain's edge, then the plane itself (docs/generator.md).
  Surface beyond = s;
  beyond.class_id = 0;
  beyond.instance_id = 0;
  GroundMeshes ground = MakeGroundMeshes(world.terrain);
  AddMesh(device, 0, std::move(ground.terrain), s);
  AddMesh(device, 1, std::move(ground.skirt), beyond);
}

void RenderScene::BuildVegetation(const EmbreeDevice& device, const WorldState& world) {
  TriangleMesh plants = VegetationMesh(world.terrain);
  if (plants.empty()) return;
  // Part of the terrain: its ids (class 0 and background when the terrain is unlabelled).
  Surface s;
  s.class_id = world.terrain.class_id;
  s.instance_id = world.terrain.instance_id;
  s.material = &FindMaterial(kVegetationMaterial, "terrain vegetation");
  const auto id = static_cast<unsigned>(ground_plane_ + 1);
  geometries_.resize(id + 1, nullptr);
  meshes_.resize(id + 1);
  surfaces_.resize(id + 1);
  AddMesh(device, id, std::move(plants), s);
  vegetation_ = static_cast<int>(id);
}

void RenderScene::RemoveVegetation() {
  if (vegetation_ < 0) return;
  const auto id = static_cast<unsigned>(vegetation_);
  Embree().detach_geometry(scene_, id);
  Embree().release_geometry(geometries_[id]);
  geometries_.resize(id);
  meshes_.resize(id);
  surfaces_.resize(id);
  vegetation_ = -1;
}

void RenderScene::SetTerrainMaterial(const SceneAssets& assets, const WorldState& world) {
  const Material* material = world.terrain_material.empty()
                                 ? assets.terrain_material
                                 : &FindMaterial(world.terrain_material, "terrain");
  for (const int id : {0, 1, ground_plane_}) surfaces_[id].material = material;
}

void RenderScene::PlaceObject(const EmbreeDevice& device,
                              const SceneAssets& assets,
                              size_t i,
                              const ObjectState& o,
                              const RenderScene* earlier) {
  if (!o.visible) return;  // invisible helpers are placed but not rendered
  const unsigned id = ObjectGeometryId(i);
  if (earlier != nullptr && i < earlier->world_.objects.size() && earlier->world_.objects[i] == o &&
      earlier->object_scenes_[i] != nullptr) {
    // Unchanged since `earlier`: its mesh, geometry and own scene as they are.
    const unsigned from = earlier->ObjectGeometryId(i);
    Embree().retain_geometry(earlier->geometries_[from]);
    AttachMesh(id, earlier->meshes_[from], earlier->geometries_[from], earlier->surfaces_[from]);
    Embree().retain_scene(earlier->object_scenes_[i]);
    object_scenes_[i] = earlier->object_scenes_[i];
    return;
  }
  const ClassShape& shape = assets.ShapeOf(i, o.asset);
  TriangleMesh mesh = ObjectMeshInWorld(shape, o);
  Surface s;
  s.object = static_cast<int>(i);
  s.class_id = o.class_id;
  s.instance_id = o.planned->instance_id;
  s.material = &FindMaterial(o.material.empty() ? shape.default_material : o.material,
                             "object '" + o.planned->name + "'");
  AddMesh(device, id, std::move(mesh), s);
  RTCScene own = Embree().new_scene(device.get());
  Embree().attach_geometry(own, geometries_[id]);
  Embree().commit_scene(own);
  object_scenes_[i] = own;
}

void RenderScene::RemoveObject(size_t i) {
  const unsigned id = ObjectGeometryId(i);
  if (geometries_[id] == nullptr) return;
  Embree().detach_geometry(scene_, id);
  Embree().release_geometry(geometries_[id]);
  geometries_[id] = nullptr;
  meshes_[id].reset();
  surfaces_[id] = Surface{};
  Embree().release_scene(object_scenes_[i]);
  object_scenes_[i] = nullptr;
}

void RenderScene::AddMesh(const EmbreeDevice& device,
                          unsigned id,
                          TriangleMesh mesh,
                          const Surface& surface) {
  // Embree reads the arrays in place (Vector3f is 3 packed floats); the last
  // vertex needs 4 readable bytes past it, so the positions are padded by one.
  mesh.positions.reserve(mesh.positions.size() + 1);
  auto shared = std::make_shared<const TriangleMesh>(std::move(mesh));
  const TriangleMesh& m = *shared;
  RTCGeometry geometry = Embree().new_geometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
  Embree().set_shared_geometry_buffer(geometry,
                                      RTC_BUFFER_TYPE_VERTEX,
                                      0,
                                      RTC_FORMAT_FLOAT3,
                                      m.positions.data(),
                                      0,
                                      sizeof(Eigen::Vector3f),
                                      m.positions.size());
  Embree().set_shared_geometry_buffer(geometry,
                                      RTC_BUFFER_TYPE_INDEX,
                                      0,
                                      RTC_FORMAT_UINT3,
                                      m.triangles.data(),
                                      0,
                                      sizeof(Eigen::Vector3i),
                                      m.triangles.size());
  Embree().commit_geometry(geometry);
  AttachMesh(id, std::move(shared), geometry, surface);
}

void RenderScene::AttachMesh(unsigned id,
                             std::shared_ptr<const TriangleMesh> mesh,
                             RTCGeometry geometry,
                             Surface surface) {
  Embree().attach_geometry_by_id(scene_, geometry, id);
  const TriangleMesh& m = *mesh;
  surface.positions = m.positions.data();
  surface.triangles = m.triangles.data();
  surface.corner_normals = m.corner_normals.empty() ? nullptr : m.corner_normals.data();
  surface.mesh = &m;
  geometries_[id] = geometry;
  meshes_[id] = std::move(mesh);
  surfaces_[id] = surface;
}

RenderScene::~RenderScene() {
  for (RTCScene s : object_scenes_) {
    if (s) Embree().release_scene(s);
  }
  for (RTCGeometry g : geometries_) {
    if (g) Embree().release_geometry(g);
  }
  Embree().release_scene(scene_);
}

}  // namespace lsds::gen
