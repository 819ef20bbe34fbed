#include "generator/scene_export/scene_export.h"

#include <cmath>
#include <deque>

#include "generator/render/exposure.h"
#include "generator/render/sky.h"
#include "generator/scene/materials.h"
#include "generator/scene/vegetation.h"
#include "generator/scene/world_ground.h"
#include "generator/scene/world_meshes.h"
#include "generator/scene_export/gltf_writer.h"
#include "generator/scene_export/sky_export.h"
#include "generator/scene_export/texture_export.h"
#include "libs/collection/json_io.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "lsds-scene-export";
constexpr const char* kFormatVersion = "1.2";
constexpr const char* kGroundFile = "ground.glb";
constexpr const char* kVegetationNode = "vegetation";

nlohmann::json Rgb(const Eigen::Vector3f& c) { return {c.x(), c.y(), c.z()}; }

GltfMaterial GltfOf(const Material& m) { return {m.name, m.base, m.roughness, m.metallic}; }

const char* PatternName(Pattern pattern) {
  switch (pattern) {
    case Pattern::kMottled:
      return "mottled";
    case Pattern::kSpeckle:
      return "speckle";
    case Pattern::kStrata:
      return "strata";
    case Pattern::kBrushed:
      return "brushed";
  }
  return "mottled";
}

// The material's record (docs/export.md): its BSDF, and the procedural albedo of
// generator/scene/materials.h as parameters (pattern, patches, ground detail).
nlohmann::json MaterialJson(const Material& material) {
  nlohmann::json json = {{"name", material.name},
                         {"base_color", Rgb(material.base)},
                         {"roughness", material.roughness},
                         {"metallic", material.metallic},
                         {"specular", material.specular}};
  if (material.contrast > 0 || material.patches > 0)
    json["pattern"] = {{"kind", PatternName(material.pattern)},
                       {"secondary_color", Rgb(material.secondary)},
                       {"frequency_per_m", material.frequency},
                       {"contrast", material.contrast},
                       {"patches", material.patches}};
  const GroundDetail& d = material.detail;
  if (d.contrast > 0)
    json["detail"] = {{"contrast", d.contrast},
                      {"coarsest_m", d.coarsest_m},
                      {"finest_m", d.finest_m},
                      {"persistence", d.persistence},
                      {"ridged_below_m", d.ridged ? kRidgedBelowM : 0.0},
                      {"tint", Rgb(d.tint)},
                      {"bump_rad", d.bump}};
  return json;
}

// A node's entry in the frame description.
nlohmann::json NodeJson(const std::string& name,
                        const std::string& file,
                        int pass_index,
                        uint32_t instance_id,
                        uint32_t class_id,
                        const Material& material) {
  return {{"name", name},
          {"file", file},
          {"pass_index", pass_index},
          {"instance_id", instance_id},
          {"class_id", class_id},
          {"material", MaterialJson(material)}};
}

// The camera as collection.json writes it (docs/format.md, "Camera model").
nlohmann::json CameraJson(const PlannedFrame& frame) {
  Frame truth;
  truth.camera.intrinsics = frame.camera;
  SetCamFromWorld(frame.cam_from_world, &truth.camera);
  return FrameToJson(truth).at("camera");
}

// The light of the frame in photometric units (radiance: RGB whose relative
// luminance is cd/m^2), as the reference renderer's Sky has it.
nlohmann::json LightJson(const Sky& sky, const PlannedEnvironment& environment) {
  const Eigen::Vector3f sun_irradiance = sky.sun_irradiance() * static_cast<float>(M_PI);
  return {{"sun",
           {{"direction_to_sun", Vector3ToJson(sky.to_sun())},
            {"irradiance", Rgb(sun_irradiance)},
            {"illuminance_lux", environment.sun.illuminance_lux},
            {"angular_diameter_deg", 0.53}}},
          {"sky",
           {{"zenith_radiance", Rgb(sky.zenith())},
            {"horizon_radiance", Rgb(sky.horizon())},
            {"below_horizon_radiance", Rgb(sky.horizon() * 0.8f)},
            {"skylight_intensity", environment.skylight_intensity},
            {"cloud_type", environment.sky.cloud_type},
            {"cloud_density", environment.sky.cloud_density}}},
          // The reference renderer's fog (Koschmieder): a surface at distance d from the camera
          // is seen as radiance * exp(-extinction * d) + fog_radiance * (1 - exp(-extinction * d)).
          {"atmosphere",
           {{"extinction_per_m", environment.fog_density}, {"fog_radiance", Rgb(sky.horizon())}}}};
}

nlohmann::json ExposureDescription(const PlannedExposure& planned) {
  if (!planned.Manual()) {
    return {{"mode", "auto"},
            {"compensation_ev", planned.compensation_ev},
            {"meter_calibration_cd_s_m2", kMeterCalibration},
            {"meter_ignored_brightest_share", kMeterIgnoredShare}};
  }
  const FrameExposure e = MeterExposure(planned, Film{});  // manual: no film is read
  return {{"mode", "manual"},
          {"ev100", e.ev100},
          {"compensation_ev", e.compensation_ev},
          {"scale", e.scale},
          {"blender_film_exposure_stops", std::log2(e.scale)}};
}

}  // namespace

SceneExporter::SceneExporter(const Plan& plan, const SceneAssets& assets, fs::path folder)
    : plan_(plan), assets_(assets), folder_(std::move(folder)), textures_(folder_) {
  // What clouds shade: the terrain and what stands on it up to kObjectsReachM. Not the skirt,
  // which reaches kilometres out: a shadow image over it would have texels wider than the
  // clouds' stripes (cirrus: 83 m apart) and lose the shadows under the camera.
  constexpr double kObjectsReachM = 50;
  ground_min_ = Eigen::Vector3d::Zero();
  ground_max_ = Eigen::Vector3d(0, 0, kObjectsReachM);
  if (plan_.terrain.present) {
    const GroundMeshes ground = MakeGroundMeshes(plan_.terrain);
    ground_min_ = Eigen::Vector3d::Constant(1e300);
    ground_max_ = -ground_min_;
    for (const Eigen::Vector3f& p : ground.terrain.positions) {
      ground_min_ = ground_min_.cwiseMin(p.cast<double>());
      ground_max_ = ground_max_.cwiseMax(p.cast<double>());
    }
    ground_max_.z() += kObjectsReachM;
  }
}

nlohmann::json SceneExporter::WriteSkyFiles(const PlannedFrame& frame,
                                            const PlannedEnvironment& environment) const {
  const Sky sky(plan_, environment);
  nlohmann::json light = LightJson(sky, environment);
  // Frames under the same sky share its images.
  const std::string key = light.dump();
  auto written = sky_files_.find(key);
  if (written == sky_files_.end()) {
    nlohmann::json files = nlohmann::json::object();
    const std::string stem = FrameStem(frame.index);
    WriteSkyImage(sky, folder_ / (stem + "_sky.exr"));
    files["image"] = stem + "_sky.exr";
    const double density =
        environment.sky.cloud_type == "none" ? 0.0 : environment.sky.cloud_density;
    if (const std::optional<CloudShadowArea> area =
            CloudShadowAreaFor(sky, density, ground_min_, ground_max_))
      files["clouds"] = WriteCloudShadowImage(sky, *area, folder_ / (stem + "_clouds.exr"));
    written = sky_files_.emplace(key, files).first;
  }
  light["sky"]["image"] = written->second["image"];
  light["sky"]["image_mapping"] = "equirectangular";
  if (written->second.contains("clouds")) light["clouds"] = written->second["clouds"];
  return light;
}

void SceneExporter::WriteGround() const {
  if (!plan_.terrain.present) return;
  const GroundMeshes ground = MakeGroundMeshes(plan_.terrain);
  const TriangleMesh plane = MakeGroundPlaneRing(plan_.terrain);
  std::vector<GltfNode> nodes = {
      {"terrain", &ground.terrain, 0}, {"skirt", &ground.skirt, 0}, {"ground_plane", &plane, 0}};
  std::vector<GltfMaterial> materials = {GltfOf(*assets_.terrain_material)};
  // The ground vegetation: the very mesh the renderer casts (docs/export.md, "Ground vegetation").
  const TriangleMesh vegetation = VegetationMesh(plan_.terrain);
  if (!vegetation.empty()) {
    nodes.push_back({kVegetationNode, &vegetation, 1});
    materials.push_back(GltfOf(FindMaterial(kVegetationMaterial, "terrain vegetation")));
  }
  WriteGlb(folder_ / kGroundFile, nodes, materials);
}

nlohmann::json SceneExporter::WriteFrame(const PlannedFrame& frame) const {
  const std::string where = "frame " + std::to_string(frame.index);
  const WorldState world = WorldAt(plan_, frame);
  const PlannedEnvironment environment = EnvironmentAt(plan_, frame);
  if (world.terrain.perlin_amplitude != plan_.terrain.perlin_amplitude ||
      world.terrain.perlin_frequency != plan_.terrain.perlin_frequency)
    throw Error(where + " changes the terrain's shape (LCAP); the scene export writes one ground " +
                "for every frame and cannot carry a second one yet");
  nlohmann::json nodes = nlohmann::json::array();
  if (plan_.terrain.present) {
    const Material& ground = FindMaterial(environment.terrain_material, where + " terrain");
    nodes.push_back(NodeJson("terrain",
                             kGroundFile,
                             kTerrainPassIndex,
                             plan_.terrain.instance_id,
                             plan_.terrain.class_id,
                             ground));
    nodes.push_back(NodeJson("skirt", kGroundFile, 0, 0, 0, ground));
    nodes.push_back(NodeJson("ground_plane", kGroundFile, 0, 0, 0, ground));
    if (PlantCount(plan_.terrain) > 0)  // part of the terrain: its pass index and ids
      nodes.push_back(NodeJson(kVegetationNode,
                               kGroundFile,
                               kTerrainPassIndex,
                               plan_.terrain.instance_id,
                               plan_.terrain.class_id,
                               FindMaterial(kVegetationMaterial, where + " vegetation")));
  }
  const std::string objects_file = FrameStem(frame.index) + ".glb";
  std::deque<TriangleMesh> meshes;  // the glTF nodes point into it
  std::vector<GltfNode> gltf_nodes;
  std::vector<GltfMaterial> materials;
  for (size_t i = 0; i < world.objects.size(); ++i) {
    const ObjectState& o = world.objects[i];
    if (!o.visible) continue;  // placed, never rendered
    const ClassShape& shape = assets_.ShapeOf(i, o.asset);
    const Material& material =
        FindMaterial(o.material.empty() ? shape.default_material : o.material,
                     where + " object '" + o.planned->name + "'");
    const std::string name = "object_" + std::to_string(i);
    meshes.push_back(ObjectMeshInWorld(shape, o));
    nodes.push_back(NodeJson(
        name, objects_file, ObjectPassIndex(i), o.planned->instance_id, o.class_id, material));
    nodes.back()["object"] = o.planned->name;
    std::vector<AlbedoPart> parts = textures_.Split(meshes.back());
    if (parts.empty()) {
      gltf_nodes.push_back({name, &meshes.back(), static_cast<int>(materials.size())});
      materials.push_back(GltfOf(material));
      continue;
    }
    // A mesh with base-colour maps: a primitive per albedo, its glTF material NAME_partK.
    meshes.pop_back();
    nlohmann::json records = nlohmann::json::array();
    for (AlbedoPart& part : parts) {
      GltfMaterial gltf = GltfOf(material);
      gltf.name = name + "_part" + std::to_string(records.size());
      if (part.constant) gltf.base_color = part.colour;
      records.push_back(part.record);
      meshes.push_back(std::move(part.mesh));
      gltf_nodes.push_back({name, &meshes.back(), static_cast<int>(materials.size())});
      materials.push_back(gltf);
    }
    nodes.back()["parts"] = records;
  }
  if (!gltf_nodes.empty()) WriteGlb(folder_ / objects_file, gltf_nodes, materials);
  nlohmann::json description = {{"format", kFormat},
                                {"format_version", kFormatVersion},
                                {"index", frame.index},
                                {"time", frame.time},
                                {"camera", CameraJson(frame)},
                                {"nodes", nodes},
                                {"exposure", ExposureDescription(plan_.exposure)}};
  description.update(WriteSkyFiles(frame, environment));
  WriteFileAtomic(folder_ / (FrameStem(frame.index) + ".json"), description.dump(2) + "\n");
  return description;
}

void SceneExporter::WriteIndex(const std::vector<int64_t>& frames) const {
  nlohmann::json listed = nlohmann::json::array();
  for (const int64_t index : frames)
    listed.push_back({{"index", index}, {"scene", FrameStem(index) + ".json"}});
  nlohmann::json classes = nlohmann::json::array();
  for (const ClassInfo& c : plan_.classes) classes.push_back({{"id", c.id}, {"name", c.name}});
  const nlohmann::json index = {
      {"format", kFormat},
      {"format_version", kFormatVersion},
      {"seed", plan_.seed},
      {"conventions",
       {{"world_frame", "ENU"},
        {"up_axis", "+z"},
        {"length_unit", "m"},
        {"gltf_from_world", "(x, y, z) -> (x, z, -y): glTF is +Y up"},
        {"camera_frame", "opencv"},
        {"pixel_coordinates", "edge"},
        {"radiance", "photometric: linear Rec. 709 RGB whose relative luminance is cd/m^2"}}},
      {"classes", classes},
      {"frames", listed}};
  WriteFileAtomic(folder_ / "scene.json", index.dump(2) + "\n");
}

std::vector<ExportedNode> SceneExporter::Nodes(const nlohmann::json& frame_description) {
  std::vector<ExportedNode> nodes;
  for (const nlohmann::json& n : frame_description.at("nodes"))
    nodes.push_back({n.at("name").get<std::string>(),
                     n.at("pass_index").get<int>(),
                     n.at("instance_id").get<uint32_t>(),
                     n.at("class_id").get<uint32_t>()});
  return nodes;
}

int64_t ExportScenes(const Plan& plan, const SceneExportOptions& options) {
  if (options.output.empty()) throw Error("no output folder (-o DIR)");
  RefuseToOverwrite(options.output, options.force, "output folder");
  // --force replaces an export (or an empty folder), never anything else.
  if (fs::exists(options.output) &&
      !(fs::is_directory(options.output) && fs::is_empty(options.output))) {
    bool export_folder = false;
    try {
      export_folder = nlohmann::json::parse(ReadFile(options.output / "scene.json"))
                          .value("format", std::string()) == kFormat;
    } catch (const std::exception&) {
    }
    if (!export_folder)
      throw Error("--force: the output exists and is not a scene export; refusing to delete it",
                  Location(options.output.string()));
  }
  const SceneAssets assets = BuildSceneAssets(plan);  // a bad material fails before any output
  std::vector<int64_t> indices;
  for (const PlannedFrame& f : plan.frames)
    if (options.frames.Contains(f.index)) indices.push_back(f.index);
  if (indices.empty())
    throw Error("no frame to export: --frames selects none of the plan's frames");
  const fs::path staging = TempPathBeside(options.output);
  fs::create_directories(staging);
  try {
    const SceneExporter exporter(plan, assets, staging);
    exporter.WriteGround();
    for (const PlannedFrame& f : plan.frames)
      if (options.frames.Contains(f.index)) exporter.WriteFrame(f);
    exporter.WriteIndex(indices);
    if (fs::exists(options.output)) fs::remove_all(options.output);
    fs::rename(staging, options.output);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
  return static_cast<int64_t>(indices.size());
}

}  // namespace lsds::gen
