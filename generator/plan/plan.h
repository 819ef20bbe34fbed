// The frame plan: what LSCENE/LCAP expand to and what the renderer consumes
// (docs/languages.md). A plan is fully sampled: no intervals or choices remain,
// every value is crisp. Its JSON form has its own schema
// (schemas/plan.schema.json).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "generator/plan/relations.h"
#include "libs/collection/model.h"
#include "libs/geometry/camera.h"
#include "libs/geometry/geodesy.h"
#include "libs/geometry/rigid3.h"

namespace lsds {

// Photometric units of the light (docs/generator.md, "Physical light and camera"). Plans written
// before them hold the sun's `intensity` and the sky's as unitless scales of a renderer whose
// radiance 1 was display white; such a legacy value v means v * kLegacyNitsPerUnit cd/m^2 of
// radiance (sky) and pi * v * kLegacyNitsPerUnit lux (sun), so old plans keep their look up to the
// camera's exposure. LSCENE itself gives lux.
constexpr double kLegacyNitsPerUnit = 10000;
// A legacy plan's sun `intensity` below this is a unitless value, not lux.
constexpr double kLegacySunIntensityLimit = 100;
double SunLuxFromIntensity(double intensity);
// The relative luminance (Rec. 709 / sRGB primaries) of a linear RGB colour.
double RelativeLuminance(const Eigen::Vector3d& rgb);

// The sky model (generator/render/sky.cc draws it): a gradient from the horizon's colour,
// 0.5 x the zenith's + kSkyHorizonWhite grey, to the zenith's; the light it gives a surface is the
// ambient radiance kSkyZenithWeight x zenith + kSkyHorizonWeight x horizon, times the skylight
// intensity.
constexpr double kSkyHorizonWhite = 0.45;
constexpr double kSkyZenithWeight = 0.6;
constexpr double kSkyHorizonWeight = 0.4;
// The illuminance (lux) on a horizontal plane, at skylight intensity 1, from a sky of colour
// `color` per cd/m^2 of zenith luminance: how a skybox `intensity` in lux becomes a luminance.
double SkyLuxPerZenithNit(const Eigen::Vector3d& color);

struct PlannedSky {
  Eigen::Vector3d color = {0.55, 0.7, 0.95};  // linear RGB at the zenith: its chromaticity
  std::string cloud_type = "none";            // none | cumulus | nimbostratus | cirrus | stratus
  double cloud_density = 0.0;                 // [0, 1]
  double luminance_cd_m2 = 7000;              // the clear sky's luminance at the zenith
};

struct PlannedSun {
  double elevation_deg = 50.0;      // above the horizon
  double azimuth_deg = 135.0;       // from north, clockwise
  double illuminance_lux = 100000;  // on a plane facing the sun, above the clouds
  // Given by date and time (geo-referenced scenes): the UTC clock at capture
  // time 0 (seconds since 1970) and the local offset it was written in. Each
  // frame's sun is then the solar position at clock + frame time.
  std::optional<double> clock_utc_s;
  double utc_offset_h = 0;
};

// An LCAP change of the terrain's shape (docs/languages.md, "Terrain shape changes"): the Perlin
// amplitude and frequency it sets; what it leaves unset stays the scene's (Plan::terrain).
struct PlannedTerrainShape {
  std::optional<double> perlin_amplitude;  // metres
  std::optional<double> perlin_frequency;  // cycles per metre
  bool empty() const { return !perlin_amplitude && !perlin_frequency; }
  bool operator==(const PlannedTerrainShape& o) const {
    return perlin_amplitude == o.perlin_amplitude && perlin_frequency == o.perlin_frequency;
  }
};

// The scene's environment: what LSCENE's sky, light, atmosphere, skylight and
// terrain material set, and what LCAP scene changes may change per frame.
struct PlannedEnvironment {
  PlannedSky sky;
  PlannedSun sun;
  double fog_density = 0.0;         // extinction per metre
  double skylight_intensity = 0.3;  // ambient
  std::string terrain_material = "grassy";
  PlannedTerrainShape terrain_shape;  // empty: the scene's terrain
  bool operator==(const PlannedEnvironment& o) const;
};

// The camera's exposure (LCAP csettings `ev100`, `iso`, `shutter`,
// `f_number`, `exposure_compensation`; docs/generator.md "Physical light and
// camera"). Manual when `ev100` or `shutter` is set, else metered per frame.
struct PlannedExposure {
  std::optional<double> ev100;      // manual, given directly
  std::optional<double> shutter_s;  // manual with f_number
  std::optional<double> f_number;   // manual with shutter_s; auto: fixed aperture (default 8)
  std::optional<double> iso;        // default 100
  double compensation_ev = 0;       // scales the exposure by 2^EV
  // The lens beside the exposure: where it focuses (the paper's focal distance; the DepthOfField
  // post-process blurs by it) and the sensor width that makes focal length and pixels metres.
  std::optional<double> focus_distance_m;
  std::optional<double> sensor_width_mm;
  bool Manual() const { return ev100.has_value() || shutter_s.has_value(); }
  bool operator==(const PlannedExposure& o) const;
};

// Ground vegetation scattered on the terrain (LSCENE `terrain{vegetation:{...}}`;
// generator/scene/vegetation.h): part of the terrain, with its ids.
struct PlannedVegetation {
  double density = 0;          // plants per square metre; 0: none
  std::string kind = "grass";  // grass | plants
  double height_m = 0.25;      // mean plant height
  uint64_t seed = 0;           // the scatter's positions, turns and sizes
  bool operator==(const PlannedVegetation& o) const {
    return density == o.density && kind == o.kind && height_m == o.height_m && seed == o.seed;
  }
};

struct PlannedTerrain {
  bool present = false;
  Eigen::Vector2d size = {200.0, 200.0};  // metres along x and y, centred on the origin
  double perlin_amplitude = 0.0;          // metres
  double perlin_frequency = 0.05;         // cycles per metre
  uint64_t perlin_seed = 0;
  std::string material = "grassy";
  uint32_t class_id = 0;     // terrain class in the class table (0: unlabeled background)
  uint32_t instance_id = 0;  // instance id in the instanceid layer
  PlannedVegetation vegetation;
};

// One object of the sampled world.
struct PlannedObject {
  std::string name;        // "O2#3": LSCENE symbol and copy number
  std::string symbol;      // "O2"
  std::string class_name;  // built-in class ("cube", "rock", ...) or a mesh file path
  uint32_t class_id = 0;
  uint32_t instance_id = 0;
  bool visible = true;  // invisible helpers are placed but not rendered
  bool target = true;   // an object of interest: gets a truth entry per frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // centre of the object's box, world metres
  Eigen::Matrix3d world_from_object = Eigen::Matrix3d::Identity();
  Eigen::Vector3d extent = Eigen::Vector3d::Ones();  // full box size in metres (after scale)
  std::string material;                              // empty: the class's default

  // How LSCENE placed it, so that LCAP changes of its size, rotation or
  // offset keep the same constraints (docs/languages.md, "Scene changes keep
  // the placement"). Not part of the plan's JSON form: the changes a capture
  // plans already carry the re-seated positions.
  enum class Support { kNone, kTerrain, kTop };
  Support support = Support::kNone;   // ON the terrain or ON another's top
  double support_top = 0;             // z of that top (kTop)
  std::vector<std::string> supports;  // symbols it may touch (ON/IN refs)
  bool overlap_allowed = true;        // overlap:true or on_overlap:allow
  // Algorithm 1's space after the object's constraints (the box its centre
  // was drawn in, z unused when it stands on a support), and its overlap
  // policy: what an LCAP re-scatter draws from again.
  Eigen::Vector3d placement_lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d placement_hi = Eigen::Vector3d::Zero();
  std::string on_overlap = "move";  // move | delete | hide | allow
  int retries = 100;
  // LSCENE `separation`: no other visible object's box within its box grown
  // by this many metres on every side (the larger of two objects' counts).
  double separation = 0;
  // Its LSCENE relations (NEAR, BEHIND, IN FRONT OF with their text), the
  // point FACING turns it to, and the eyes VISIBLE FROM must see it from (with
  // the viewer's name, which never blocks its own view): a re-scatter keeps
  // them.
  std::vector<std::pair<Relation, std::string>> relations;
  std::optional<Eigen::Vector3d> facing;
  struct Sight {
    Eigen::Vector3d eye = Eigen::Vector3d::Zero();
    std::string viewer;  // PlannedObject::name, empty for a point
    std::string what;
  };
  std::vector<Sight> sights;
};

// A change to an object in effect on a frame (LCAP scene changes:
// when/after/during).
struct ObjectChange {
  std::string object;  // PlannedObject::name
  std::optional<Eigen::Vector3d> position;
  std::optional<Eigen::Matrix3d> world_from_object;
  std::optional<Eigen::Vector3d> extent;
  std::optional<std::string> material;
  std::optional<bool> visible;
  // A class or asset swap: the asset drawn from this frame on (built-in
  // class or mesh path, at its own size: the change's extent) and its class id.
  std::optional<std::string> asset;
  std::optional<uint32_t> class_id;
  // The object's velocity (world m/s) when it moves along a path.
  std::optional<Eigen::Vector3d> velocity;
};

struct PlannedFrame {
  int64_t index = 0;
  double time = 0;       // seconds
  std::string sequence;  // path instance, e.g. "P1(2)"
  // Index of the first frame of this frame's continuous shot: a path flown
  // continuously (waypoints, one altitude level of a grid) is one shot; each
  // discrete pose (hemi, random, create point) starts one. Motion vectors are
  // measured only within a shot.
  int64_t shot = 0;
  PinholeCamera camera;
  Rigid3d cam_from_world;
  // The camera centre's velocity, world m/s, on smooth flights.
  std::optional<Eigen::Vector3d> camera_velocity;
  std::vector<ObjectChange> changes;  // applied in order on top of the world's objects
  // The environment in effect when LCAP changes it (sky, sun, atmosphere,
  // skylight, terrain material); absent: the plan's.
  std::optional<PlannedEnvironment> environment;
  // A rig capture (Plan::rig): the rig camera of this frame and the time step
  // it shares with the rig's other cameras (docs/languages.md, "Camera rigs").
  std::optional<std::string> rig_camera;
  int64_t step = -1;  // -1: not a rig frame
  // LCAP requirements and quotas demanded of this frame: {attempts, met,
  // checks: [{name, object, quantity, min, max, estimate, met}]}
  // (generator/lang/requirements.h); absent without requirements.
  std::optional<nlohmann::json> requirements;
};

struct Plan {
  uint64_t seed = 0;
  // What planning found doubtful but kept (implausible light values), located; printed by `lsds
  // plan` and `lsds generate`, not part of the plan's JSON.
  std::vector<std::string> warnings;
  std::optional<GeoOrigin> geo;  // LSCENE georeference: the world is ENU there
  std::string scene_source;      // LSCENE text, verbatim
  std::string capture_source;    // LCAP text, verbatim
  std::vector<ClassInfo> classes;
  PlannedSky sky;
  PlannedSun sun;
  double fog_density = 0.0;         // per metre
  double skylight_intensity = 0.3;  // ambient
  PlannedTerrain terrain;
  std::vector<PlannedObject> objects;
  std::vector<std::string>
      post_process;          // PP materials named in LCAP, recorded as capture settings
  PlannedExposure exposure;  // LCAP csettings, the same for every frame
  // LCAP capture settings other than post-process materials (e.g. "layers",
  // "output"), as written.
  nlohmann::json capture_settings = nlohmann::json::object();
  // Several cameras on one platform (LCAP camera `rig`): frames of one time
  // step are consecutive, in this order.
  std::optional<Rig> rig;
  std::vector<PlannedFrame> frames;
  // What the capture's requirements and quotas ask (with the planned count of
  // every quota bin); null without requirements. Goes to
  // collection.json provenance.requirements.
  nlohmann::json requirements;
};

// The plan's own environment, and the one in effect on `frame`.
PlannedEnvironment EnvironmentOf(const Plan& plan);
PlannedEnvironment EnvironmentAt(const Plan& plan, const PlannedFrame& frame);
// Writes `environment` back into the plan's own fields (a terrain shape change too).
void SetEnvironment(const PlannedEnvironment& environment, Plan* plan);
// The terrain `environment` shows: the plan's, with the environment's shape change.
PlannedTerrain TerrainOf(const Plan& plan, const PlannedEnvironment& environment);
// The terrain in effect on `frame`.
PlannedTerrain TerrainAt(const Plan& plan, const PlannedFrame& frame);
// Whether some frame of `plan` changes the terrain's shape.
bool TerrainShapeChanges(const Plan& plan);

}  // namespace lsds
