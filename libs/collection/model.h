// The in-memory model of a collection (docs/format.md). Plain structs; JSON I/O
// lives in json_io.h.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "libs/collection/bundle_layout.h"
#include "libs/exr/exr_types.h"
#include "libs/geometry/attitude.h"
#include "libs/geometry/box2d.h"
#include "libs/geometry/camera.h"
#include "libs/geometry/geodesy.h"
#include "libs/geometry/oriented_box.h"
#include "libs/geometry/oriented_box2d.h"
#include "libs/geometry/rigid3.h"
#include "libs/geometry/world_frame.h"

namespace lsds {

inline constexpr const char* kCollectionFormat = "lsds-collection";
inline constexpr const char* kMetadataFormat = "lsds-metadata";
inline constexpr const char* kFormatVersion = "1.2";
inline constexpr const char* kCollectionFile = "collection.json";
inline constexpr const char* kMetadataFile = "metadata.json";

struct ClassInfo {
  uint32_t id = 0;  // > 0; 0 is background
  std::string name;
};

struct LayerChannel {
  std::string name;
  exr::PixelType type = exr::PixelType::kFloat;
};

// How a worldposition layer stores its values (format 1.1; the codec and the one
// reader are in libs/collection/worldposition_layout.h).
enum class FlatLayout { kFloat, kResidual };

// One entry of the layer table: a folder of one EXR per frame.
struct LayerInfo {
  std::string name;      // folder name, e.g. "depth"
  std::string semantic;  // rgb | classid | instanceid | depth | normal |
                         // worldposition | shadow | motion | bundle | derived
  bool deep = false;
  std::vector<LayerChannel> channels;
  std::string unit;                     // free text for people: "m", "unit vector",
                                        // "screen-normalized", ...
  std::optional<DepthKind> depth_kind;  // depth layers and deep bundles
  exr::Compression compression = exr::Compression::kZip;
  bool required = true;  // every frame has a file for it
  // Deep bundle layers (format 1.1): how the file stores the samples
  // (libs/collection/bundle_layout.h); readers yield the same samples either way.
  BundleLayout layout = BundleLayout::kFull;
  // Worldposition layers (format 1.1, the same `layout` key): float or
  // residual; readers yield the same X, Y, Z either way.
  FlatLayout flat_layout = FlatLayout::kFloat;
  std::string description;

  const LayerChannel* FindChannel(const std::string& channel) const;
};

// Format 1.1, optional: the collection is shard `index` of `count` of one run
// (`lsds generate --shard I/N`): it holds the run's frames whose index % count
// == index. `lsds merge` joins the shards into the run's collection
// (docs/scale-out.md).
struct ShardRecord {
  int index = 0;
  int count = 1;
  // The frames of the whole run, all shards together: `run_frame_count`
  // indices from `run_first_frame` to `run_last_frame` (inclusive).
  int64_t run_first_frame = 0;
  int64_t run_last_frame = 0;
  int64_t run_frame_count = 0;
};

struct Provenance {
  std::string generator;  // "lsds generate", "lsds synth", ...
  std::string generator_version;
  std::optional<uint64_t> seed;
  std::string scene_source;                          // LSCENE text, verbatim
  std::string capture_source;                        // LCAP text, verbatim
  nlohmann::json render = nlohmann::json::object();  // spp, renderer settings, ...
  // Format 1.1, imported collections only (docs/format.md, "Truth of other
  // origins"): {"format", "source", "truth_origin": {field: origin}}; null
  // for collections lsds rendered.
  nlohmann::json import;
  std::optional<ShardRecord> shard;  // set only in a shard of a run
  // Format 1.1, optional: what the capture's requirements and quotas asked
  // (docs/languages.md, "Requirements and quotas"), with the planned count of
  // every quota bin; null without requirements.
  nlohmann::json requirements;
};

// Declared units and frames (docs/format.md, "Units and frames").
struct Conventions {
  WorldFrame world = WorldFrame::Make("ENU", "m");
  // Fixed in format 1.0, written so that readers never have to guess.
  std::string camera_frame = "opencv";       // x right, y down, z forward
  std::string pixel_coordinates = "edge";    // pixel (i, j) covers [i, i+1) x [j, j+1)
  std::string motion = "screen-normalized";  // 0.5 + 0.5 * (current - previous) / size
  // Format 1.1, optional: where the world origin is on Earth (the world frame
  // is then local ENU at that origin).
  std::optional<GeoOrigin> geo_origin;
};

// A registered metadata variant (metadata.json and perturbed copies).
struct MetadataVariant {
  std::string file;  // relative to the collection root
  bool perturbed = false;
  std::string description;
};

struct CameraTruth {
  PinholeCamera intrinsics;
  // As declared (world units; the rotation has determinant -1 for a left-handed
  // world).
  Eigen::Matrix3d cam_from_world_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d cam_from_world_translation = Eigen::Vector3d::Zero();
};

struct ObjectTruth {
  uint32_t instance_id = 0;  // > 0, the value in the instanceid layer
  uint32_t class_id = 0;     // > 0, an id of the class table
  std::string name;          // e.g. "O2#3": the LSCENE symbol and its copy
  // World frame, world units. Format 1.2: absent for an imported object its
  // source gives only a 2D box for (docs/format.md, "Objects without a 3D box").
  std::optional<OrientedBox> obb;
  std::optional<Box2d> bbox;            // tight, visible: extent of the instance mask;
                                        // none when not visible
  std::optional<Box2d> bbox_projected;  // loose: bounds of the projected OBB
                                        // clipped to the image
  // Format 1.2, optional (docs/format.md, "Oriented boxes"): the visible
  // oriented box, the minimum-area rectangle of the instance mask on pixel
  // edges (none when not visible), and the amodal one, the minimum-area
  // rectangle of the projected 3D OBB (clipped at the near plane, not to the
  // image). Heading corner first where the object's heading is known.
  std::optional<OrientedBox2d> bbox_oriented;
  std::optional<OrientedBox2d> bbox_oriented_projected;
  int64_t visible_pixels = 0;
  double visibility = 0;  // visible pixels / pixels covered with no occluders, in [0, 1]
  double in_frame = 0;    // share of the projected silhouette inside the image, in [0, 1]
  // Format 1.1, optional: what was drawn and how it was seen.
  std::string asset;                    // the asset the object was drawn from ("barrel", a mesh)
  std::string material;                 // the material applied in this frame, if known
  std::optional<double> transmittance;  // atmospheric, camera to OBB centre
  // World units per second: the OBB centre's velocity (0 at rest).
  std::optional<Eigen::Vector3d> velocity;
  nlohmann::json changes;  // LCAP changes in effect at this frame (null: none)
};

struct Frame {
  int64_t index = 0;
  double time = 0;       // seconds
  std::string sequence;  // frames of one path/sequence; splits never cut one
  // Format 1.1: index of the first frame of this frame's continuous shot.
  // Motion is measured against the previous frame only within a shot. Absent
  // in 1.0 collections, where the sequence plays that role.
  std::optional<int64_t> shot;
  // Format 1.1: the scene state the frame shows (sun, sky, atmosphere), as
  // written by the generator; null when unknown.
  nlohmann::json scene;
  // Format 1.1, optional: the camera exposure the rgb layer was exposed with
  // (docs/format.md, "Exposure"); null when unknown.
  nlohmann::json exposure;
  CameraTruth camera;
  // Format 1.1, optional: the camera centre's velocity (world units per
  // second) on a smooth flight.
  std::optional<Eigen::Vector3d> camera_velocity;
  // Format 1.1, optional: the requirements and quota bins demanded of this
  // frame, with the planner's estimate and the value achieved in this truth
  // (docs/format.md); null without requirements.
  nlohmann::json requirements;
  std::map<std::string, std::string> files;  // layer name -> path relative to the collection root
  std::vector<ObjectTruth> objects;
  // Format 1.1, optional: in a rig collection (CollectionHeader::rig), the
  // camera of the rig this frame is from and the time step it shares with the
  // other cameras of the rig (docs/format.md, "Camera rigs").
  std::optional<std::string> rig_camera;
  std::optional<int64_t> step;
};

// Format 1.1, optional: several cameras on one platform moving together
// (docs/format.md, "Camera rigs"). Each camera's pose is fixed relative to
// the rig: cam_from_world = cam_from_rig * rig_from_world.
struct RigCamera {
  std::string name;  // "left": frames[k].rig_camera, and the file name suffix
  PinholeCamera intrinsics;
  Rigid3d cam_from_rig;
};

struct Rig {
  std::vector<RigCamera> cameras;  // in frame order within a time step
  const RigCamera* Find(const std::string& name) const;
};

// Everything in collection.json except the frames, which are streamed.
struct CollectionHeader {
  std::string format_version = kFormatVersion;
  Provenance provenance;
  Conventions conventions;
  std::vector<ClassInfo> classes;
  std::vector<LayerInfo> layers;
  std::vector<MetadataVariant> metadata;
  int64_t frame_count = 0;
  std::optional<Rig> rig;  // format 1.1: a camera rig (absent: one camera)

  const LayerInfo* FindLayer(const std::string& name) const;
  const LayerInfo* FindLayerBySemantic(const std::string& semantic) const;
  const ClassInfo* FindClass(uint32_t id) const;
};

// The frame's camera as every EXR of the frame carries it in its header
// (docs/format.md, "EXR header camera").
exr::HeaderCamera HeaderCameraOf(const CameraTruth& camera);

// The one conversion between the camera pose's two forms: the declared
// matrices of collection.json (CameraTruth) and the rigid transform the
// geometry code computes with (Rigid3d). The rotation becomes a normalized
// quaternion, which is meaningful only for a right-handed world (determinant
// +1); callers check the determinant where a left-handed world may occur.
Rigid3d CamFromWorld(const CameraTruth& camera);
void SetCamFromWorld(const Rigid3d& cam_from_world, CameraTruth* camera);

// The standard layer table entries of docs/format.md.
LayerInfo StandardLayer(const std::string& semantic, DepthKind depth_kind = DepthKind::kPlanar);
const std::vector<std::string>& StandardLayerSemantics();

// --- metadata.json ---

struct NoiseRecord {  // what perturb-metadata did; absent for truth
  std::string model;
  nlohmann::json parameters = nlohmann::json::object();
  uint64_t seed = 0;
};

struct MetadataFrame {
  int64_t index = 0;
  double time = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // camera centre, world frame and units
  Attitude attitude;                                   // see libs/geometry/attitude.h
  PinholeCamera camera;
  nlohmann::json error;  // realized errors when perturbed, else null
  // Format 1.1, optional: what a UAV logs besides its pose.
  std::optional<Geodetic> geo;           // when the world is geo-referenced
  std::optional<double> altitude_agl_m;  // above the terrain under the camera
  std::optional<double> gsd_m;           // ground sample distance at the image centre
  // The image corners (top-left, top-right, bottom-right, bottom-left) on the
  // ground, world frame; empty when a corner ray misses the ground.
  std::vector<Eigen::Vector3d> footprint;
};

struct MetadataHeader {
  std::string format_version = kFormatVersion;
  bool perturbed = false;
  std::optional<NoiseRecord> noise;
  std::string source;  // the metadata file this one was derived from, if any
  int64_t frame_count = 0;
};

}  // namespace lsds
