// The Embree device and the ray-tracing scene of one world state: terrain plus
// every rendered object, transformed to world coordinates once. Each rendered
// object also gets a scene of its own (sharing its geometry) for the unoccluded
// coverage that visibility fractions need. An object in the same state as in
// an earlier frame's scene shares that scene's world-space mesh, geometry and
// own scene instead of building them again, and a scene can be moved to
// another world state in place (Update), rebuilding only what changed.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "generator/plan/plan.h"
#include "generator/scene/materials.h"
#include "generator/scene/object_library.h"
#include "generator/scene/world.h"

namespace lsds::gen {

class EmbreeDevice {
 public:
  EmbreeDevice();  // throws lsds::Error when Embree cannot start
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;
  RTCDevice get() const { return device_; }

 private:
  RTCDevice device_ = nullptr;
};

// Per-plan assets built once: each object's class shape and the materials
// (validated up front so that a bad name fails before any frame is rendered).
struct SceneAssets {
  std::vector<ClassShape> shapes;  // per Plan::objects entry
  // Shapes LCAP class changes swap in: (object index, asset) -> shape.
  std::map<std::pair<size_t, std::string>, ClassShape> swapped;
  // The shape object `i` draws as `asset`.
  const ClassShape& ShapeOf(size_t i, const std::string& asset) const;
  const Material* terrain_material = nullptr;
  size_t vegetation_triangles = 0;  // of the ground vegetation (vegetation.h)
};
SceneAssets BuildSceneAssets(const Plan& plan);

// About how many bytes a frame's RenderScene takes for these assets: each object's mesh in its own
// frame and in world space with its corner normals, and the Embree BVHs over it. Measured, not
// derived: 280 bytes a triangle (4,000 vehicles and people, 3.4 M triangles, took 0.92 GB over
// the empty scene's peak). Generate checks it against the memory budget before any output.
double RenderSceneBytes(const SceneAssets& assets);

// What a hit on a geometry means.
struct Surface {
  int object = -1;  // index in WorldState::objects, -1 for the terrain
  uint32_t class_id = 0;
  uint32_t instance_id = 0;
  const Material* material = nullptr;
  const Eigen::Vector3f* positions = nullptr;  // world-space vertices of the geometry
  const Eigen::Vector3i* triangles = nullptr;
  // Shading normals, 3 per triangle (TriangleMesh::corner_normals); null: flat.
  const Eigen::Vector3f* corner_normals = nullptr;
  const TriangleMesh* mesh = nullptr;  // the geometry's mesh (null: the ground plane)

  // The base-colour map's bilinear texel at barycentrics (u, v) of triangle
  // `prim` (Embree's convention: (1-u-v) v0 + u v1 + v v2), or nullopt when
  // the triangle has no image texture (then the material's albedo holds).
  std::optional<Eigen::Vector3f> MappedAlbedo(unsigned prim, float u, float v) const;
};

class RenderScene {
 public:
  // `earlier`, when given, is another world state's scene (usually the
  // previous frame's): its objects whose ObjectState is unchanged are shared,
  // not rebuilt. The scene is the same either way.
  RenderScene(const EmbreeDevice& device,
              const Plan& plan,
              const SceneAssets& assets,
              const WorldState& world,
              const RenderScene* earlier = nullptr);
  ~RenderScene();
  RenderScene(const RenderScene&) = delete;
  RenderScene& operator=(const RenderScene&) = delete;

  // Makes this the scene of `world` (a world state of the same plan), as if
  // built afresh with `earlier`: the objects whose state did not change keep
  // their geometry and its BVH, so Embree rebuilds only the changed objects'
  // BVHs and the level above them; changed objects are shared from
  // `earlier` where it has them in their new state, else built. The terrain
  // is meshed again when its shape changed (else only its material follows
  // the world).
  void Update(const EmbreeDevice& device,
              const SceneAssets& assets,
              const WorldState& world,
              const RenderScene* earlier = nullptr);

  RTCScene scene() const { return scene_; }
  // The scene holding only object `object` (nullptr when it is not rendered).
  RTCScene ObjectScene(int object) const { return object_scenes_[object]; }
  const Surface& surface(unsigned geom_id) const { return surfaces_[geom_id]; }
  // Surface ids run from 0 to surface_count() - 1: the terrain and its skirt
  // (0 and 1, when the plan has terrain), one per object of the world in its
  // order (a default Surface, with no mesh, while the object is not
  // rendered), then the ground plane, then the ground vegetation when the
  // terrain has it (one geometry of every plant, carrying the terrain's ids).
  size_t surface_count() const { return surfaces_.size(); }
  const WorldState& world() const { return world_; }
  // The plane z = kWorldGroundZ past the world ground's skirt
  // (generator/scene/world_ground.h): the surface id a ray that misses every
  // geometry but meets that plane reports (no Embree geometry), or -1 when
  // the plan has no terrain.
  int ground_plane() const { return ground_plane_; }

 private:
  // The geometry id of object `i` (fixed: an object keeps its id across
  // updates, which keeps the ids, and so the BVH, those of a fresh scene).
  unsigned ObjectGeometryId(size_t i) const { return first_object_id_ + static_cast<unsigned>(i); }
  // Object `i` in state `o`: kept when this scene has it so already, else
  // shared from `earlier` or built, or removed when `o` is not rendered.
  void PlaceObject(const EmbreeDevice& device,
                   const SceneAssets& assets,
                   size_t i,
                   const ObjectState& o,
                   const RenderScene* earlier);
  void RemoveObject(size_t i);
  // The terrain of `world` and its skirt, as geometries 0 and 1 (their
  // material is set by SetTerrainMaterial).
  void BuildGround(const EmbreeDevice& device, const WorldState& world);
  // The terrain's vegetation (generator/scene/vegetation.h): every plant in one world-space
  // geometry, the id after the ground plane; and its removal.
  void BuildVegetation(const EmbreeDevice& device, const WorldState& world);
  void RemoveVegetation();
  // The terrain's material in `world` (LCAP may change it per frame).
  void SetTerrainMaterial(const SceneAssets& assets, const WorldState& world);
  // A new Embree geometry reading `mesh` in place, attached as `id`
  // (AttachMesh).
  void AddMesh(const EmbreeDevice& device, unsigned id, TriangleMesh mesh, const Surface& surface);
  // Attaches `geometry` (one reference of it passes to this scene) reading
  // `mesh`, as geometry id `id`.
  void AttachMesh(unsigned id,
                  std::shared_ptr<const TriangleMesh> mesh,
                  RTCGeometry geometry,
                  Surface surface);

  WorldState world_;
  RTCScene scene_ = nullptr;
  unsigned first_object_id_ = 0;         // 2 with terrain (terrain, skirt), else 0
  std::vector<RTCScene> object_scenes_;  // per object, nullptr when not rendered
  // By geometry id: the geometry (nullptr where none is attached), its
  // world-space mesh (shared with the scenes that reuse it) and what a hit on
  // it means.
  std::vector<RTCGeometry> geometries_;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes_;
  std::vector<Surface> surfaces_;
  int ground_plane_ = -1;
  int vegetation_ = -1;  // the vegetation's geometry id, -1: none
};

}  // namespace lsds::gen
