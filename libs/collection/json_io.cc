#include "libs/collection/json_io.h"

#include <algorithm>

#include "libs/collection/worldposition_layout.h"
#include "libs/util/confined_path.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/strings.h"
#include "libs/util/text_check.h"

namespace lsds {

using nlohmann::json;

json Vector3ToJson(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json Matrix3ToJson(const Eigen::Matrix3d& m) {
  json rows = json::array();
  for (int r = 0; r < 3; ++r) rows.push_back(json::array({m(r, 0), m(r, 1), m(r, 2)}));
  return rows;
}

json Box2dToJson(const std::optional<Box2d>& box) {
  if (!box) return nullptr;
  return json::array({box->x0, box->y0, box->x1, box->y1});
}

namespace {

Eigen::Vector3d Vector3FromJson(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

Eigen::Matrix3d Matrix3FromJson(const json& j) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = j.at(r).at(c).get<double>();
  }
  return m;
}

std::optional<Box2d> Box2dFromJson(const json& j) {
  if (j.is_null()) return std::nullopt;
  return Box2d{
      j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>(), j.at(3).get<double>()};
}

// An oriented box as its four [x, y] corners, in order (docs/format.md,
// "Oriented boxes").
json OrientedBox2dToJson(const OrientedBox2d& box) {
  json corners = json::array();
  for (const Eigen::Vector2d& c : box.corners) corners.push_back(json::array({c.x(), c.y()}));
  return corners;
}

OrientedBox2d OrientedBox2dFromJson(const json& j) {
  OrientedBox2d box;
  for (size_t i = 0; i < box.corners.size(); ++i)
    box.corners[i] = {j.at(i).at(0).get<double>(), j.at(i).at(1).get<double>()};
  return box;
}

// File references in a collection resolve strictly inside it: relative, with no
// ".." component (docs/format.md, "File references"). Throws lsds::Error at
// `file#pointer`.
void CheckInsideReference(const std::string& reference,
                          const std::string& file,
                          const std::string& pointer) {
  const std::string problem = ReferenceProblem(reference, "the collection");
  if (problem.empty()) return;
  throw Error("file reference '" + Excerpt(reference) + "' " + problem +
                  "; references must be relative paths inside the collection",
              Location(file, pointer));
}

json LayerToJson(const LayerInfo& layer) {
  json channels = json::array();
  for (const LayerChannel& c : layer.channels) {
    channels.push_back({{"name", c.name}, {"type", exr::PixelTypeName(c.type)}});
  }
  json j = {{"name", layer.name},
            {"semantic", layer.semantic},
            {"deep", layer.deep},
            {"channels", channels},
            {"compression", exr::CompressionName(layer.compression)},
            {"required", layer.required}};
  if (!layer.unit.empty()) j["unit"] = layer.unit;
  if (layer.depth_kind) j["depth_kind"] = DepthKindName(*layer.depth_kind);
  if (!layer.description.empty()) j["description"] = layer.description;
  if (layer.layout != BundleLayout::kFull) j["layout"] = BundleLayoutName(layer.layout);
  if (layer.flat_layout != FlatLayout::kFloat) j["layout"] = FlatLayoutName(layer.flat_layout);
  return j;
}

LayerInfo LayerFromJson(const json& j) {
  LayerInfo layer;
  layer.name = j.at("name").get<std::string>();
  layer.semantic = j.at("semantic").get<std::string>();
  layer.deep = j.at("deep").get<bool>();
  for (const json& c : j.at("channels")) {
    LayerChannel channel;
    channel.name = c.at("name").get<std::string>();
    exr::ParsePixelType(c.at("type").get<std::string>(), &channel.type);
    layer.channels.push_back(channel);
  }
  layer.unit = j.value("unit", "");
  if (j.contains("depth_kind")) {
    DepthKind kind;
    ParseDepthKind(j.at("depth_kind").get<std::string>(), &kind);
    layer.depth_kind = kind;
  }
  exr::ParseCompression(j.value("compression", "zip"), &layer.compression);
  layer.required = j.at("required").get<bool>();
  layer.description = j.value("description", "");
  // One key, two vocabularies: the bundle's full | compact | residual, the
  // worldposition's and motion's float | residual (the schema allows all).
  if (j.contains("layout")) {
    const std::string layout = j.at("layout").get<std::string>();
    if (layer.semantic == "worldposition" || layer.semantic == "motion") {
      ParseFlatLayout(layout, &layer.flat_layout);
    } else {
      ParseBundleLayout(layout, &layer.layout);
    }
  }
  return layer;
}

json CameraToJson(const CameraTruth& camera) {
  const PinholeCamera& k = camera.intrinsics;
  return {{"model", "pinhole"},
          {"width", k.width},
          {"height", k.height},
          {"fx", k.fx},
          {"fy", k.fy},
          {"cx", k.cx},
          {"cy", k.cy},
          {"cam_from_world",
           {{"rotation", Matrix3ToJson(camera.cam_from_world_rotation)},
            {"translation", Vector3ToJson(camera.cam_from_world_translation)}}}};
}

CameraTruth CameraFromJson(const json& j) {
  CameraTruth camera;
  camera.intrinsics.width = GetInteger<int>(j, "width");
  camera.intrinsics.height = GetInteger<int>(j, "height");
  camera.intrinsics.fx = j.at("fx").get<double>();
  camera.intrinsics.fy = j.at("fy").get<double>();
  camera.intrinsics.cx = j.at("cx").get<double>();
  camera.intrinsics.cy = j.at("cy").get<double>();
  camera.cam_from_world_rotation = Matrix3FromJson(j.at("cam_from_world").at("rotation"));
  camera.cam_from_world_translation = Vector3FromJson(j.at("cam_from_world").at("translation"));
  return camera;
}

json ObjectToJson(const ObjectTruth& o) {
  json j = {{"instance_id", o.instance_id},
            {"class_id", o.class_id},
            {"bbox", Box2dToJson(o.bbox)},
            {"bbox_projected", Box2dToJson(o.bbox_projected)},
            {"visible_pixels", o.visible_pixels},
            {"visibility", o.visibility},
            {"in_frame", o.in_frame}};
  if (!o.name.empty()) j["name"] = o.name;
  if (o.obb)
    j["obb"] = {{"center", Vector3ToJson(o.obb->center)},
                {"half_extents", Vector3ToJson(o.obb->half_extents)},
                {"rotation", Matrix3ToJson(o.obb->world_from_box)}};
  if (o.bbox_oriented) j["bbox_oriented"] = OrientedBox2dToJson(*o.bbox_oriented);
  if (o.bbox_oriented_projected)
    j["bbox_oriented_projected"] = OrientedBox2dToJson(*o.bbox_oriented_projected);
  if (!o.asset.empty()) j["asset"] = o.asset;
  if (!o.material.empty()) j["material"] = o.material;
  if (o.transmittance) j["transmittance"] = *o.transmittance;
  if (o.velocity) j["velocity"] = Vector3ToJson(*o.velocity);
  if (!o.changes.is_null()) j["changes"] = o.changes;
  return j;
}

ObjectTruth ObjectFromJson(const json& j) {
  ObjectTruth o;
  o.instance_id = GetInteger<uint32_t>(j, "instance_id");
  o.class_id = GetInteger<uint32_t>(j, "class_id");
  o.name = j.value("name", "");
  if (j.contains("obb")) {
    OrientedBox& obb = o.obb.emplace();
    obb.center = Vector3FromJson(j.at("obb").at("center"));
    obb.half_extents = Vector3FromJson(j.at("obb").at("half_extents"));
    obb.world_from_box = Matrix3FromJson(j.at("obb").at("rotation"));
  }
  o.bbox = Box2dFromJson(j.at("bbox"));
  o.bbox_projected =
      j.contains("bbox_projected") ? Box2dFromJson(j.at("bbox_projected")) : std::nullopt;
  if (j.contains("bbox_oriented")) o.bbox_oriented = OrientedBox2dFromJson(j.at("bbox_oriented"));
  if (j.contains("bbox_oriented_projected"))
    o.bbox_oriented_projected = OrientedBox2dFromJson(j.at("bbox_oriented_projected"));
  o.visible_pixels = j.at("visible_pixels").get<int64_t>();
  o.visibility = j.at("visibility").get<double>();
  o.in_frame = j.at("in_frame").get<double>();
  o.asset = j.value("asset", "");
  o.material = j.value("material", "");
  if (j.contains("transmittance")) o.transmittance = j.at("transmittance").get<double>();
  if (j.contains("velocity")) o.velocity = Vector3FromJson(j.at("velocity"));
  if (j.contains("changes")) o.changes = j.at("changes");
  return o;
}

}  // namespace

json RigToJson(const Rig& rig) {
  json cameras = json::array();
  for (const RigCamera& c : rig.cameras) {
    const PinholeCamera& k = c.intrinsics;
    cameras.push_back({{"name", c.name},
                       {"width", k.width},
                       {"height", k.height},
                       {"fx", k.fx},
                       {"fy", k.fy},
                       {"cx", k.cx},
                       {"cy", k.cy},
                       {"cam_from_rig",
                        {{"rotation", Matrix3ToJson(c.cam_from_rig.rotation.toRotationMatrix())},
                         {"translation", Vector3ToJson(c.cam_from_rig.translation)}}}});
  }
  return {{"cameras", cameras}};
}

Rig RigFromJson(const json& j) {
  Rig rig;
  for (const json& c : j.at("cameras")) {
    RigCamera camera;
    camera.name = c.at("name").get<std::string>();
    camera.intrinsics.width = GetInteger<int>(c, "width");
    camera.intrinsics.height = GetInteger<int>(c, "height");
    camera.intrinsics.fx = c.at("fx").get<double>();
    camera.intrinsics.fy = c.at("fy").get<double>();
    camera.intrinsics.cx = c.at("cx").get<double>();
    camera.intrinsics.cy = c.at("cy").get<double>();
    camera.cam_from_rig.rotation =
        Eigen::Quaterniond(Matrix3FromJson(c.at("cam_from_rig").at("rotation"))).normalized();
    camera.cam_from_rig.translation = Vector3FromJson(c.at("cam_from_rig").at("translation"));
    rig.cameras.push_back(camera);
  }
  return rig;
}

json HeaderToJson(const CollectionHeader& h) {
  json provenance = {{"generator", h.provenance.generator},
                     {"generator_version", h.provenance.generator_version},
                     {"render", h.provenance.render}};
  if (h.provenance.seed) provenance["seed"] = *h.provenance.seed;
  if (!h.provenance.scene_source.empty()) provenance["scene_source"] = h.provenance.scene_source;
  if (!h.provenance.capture_source.empty())
    provenance["capture_source"] = h.provenance.capture_source;
  if (!h.provenance.import.is_null()) provenance["import"] = h.provenance.import;
  if (!h.provenance.requirements.is_null()) provenance["requirements"] = h.provenance.requirements;
  if (const auto& shard = h.provenance.shard)
    provenance["shard"] = {{"index", shard->index},
                           {"count", shard->count},
                           {"run_frames",
                            {{"first", shard->run_first_frame},
                             {"last", shard->run_last_frame},
                             {"count", shard->run_frame_count}}}};
  const WorldFrame& world = h.conventions.world;
  json conventions = {{"world_frame", world.name},
                      {"length_unit", world.length_unit},
                      {"handedness", world.right_handed() ? "right" : "left"},
                      {"up_axis", world.name == "NED" ? "-z" : "+z"},
                      {"camera_frame", h.conventions.camera_frame},
                      {"pixel_coordinates", h.conventions.pixel_coordinates},
                      {"motion", h.conventions.motion}};
  if (const auto& geo = h.conventions.geo_origin)
    conventions["geo_origin"] = {{"latitude_deg", geo->latitude_deg},
                                 {"longitude_deg", geo->longitude_deg},
                                 {"altitude_m", geo->altitude_m}};
  json classes = json::array();
  for (const ClassInfo& c : h.classes) classes.push_back({{"id", c.id}, {"name", c.name}});
  json layers = json::array();
  for (const LayerInfo& layer : h.layers) layers.push_back(LayerToJson(layer));
  json metadata = json::array();
  for (const MetadataVariant& m : h.metadata) {
    json entry = {{"file", m.file}, {"perturbed", m.perturbed}};
    if (!m.description.empty()) entry["description"] = m.description;
    metadata.push_back(entry);
  }
  json header = {{"format", kCollectionFormat},
                 {"format_version", h.format_version},
                 {"provenance", provenance},
                 {"conventions", conventions},
                 {"classes", classes},
                 {"layers", layers},
                 {"metadata", metadata},
                 {"frame_count", h.frame_count},
                 {"frames", json::array()}};
  if (h.rig) header["rig"] = RigToJson(*h.rig);
  return header;
}

CollectionHeader HeaderFromJson(const json& j, const std::string& file) {
  CollectionHeader h;
  AtPointer(file, "", [&] {
    h.format_version = j.at("format_version").get<std::string>();
    const json& p = j.at("provenance");
    h.provenance.generator = p.at("generator").get<std::string>();
    h.provenance.generator_version = p.at("generator_version").get<std::string>();
    if (p.contains("seed")) h.provenance.seed = GetInteger<uint64_t>(p, "seed");
    h.provenance.scene_source = p.value("scene_source", "");
    h.provenance.capture_source = p.value("capture_source", "");
    h.provenance.render = p.value("render", json::object());
    if (p.contains("import")) h.provenance.import = p.at("import");
    if (p.contains("requirements")) h.provenance.requirements = p.at("requirements");
    if (p.contains("shard")) {
      const json& s = p.at("shard");
      ShardRecord shard;
      shard.index = GetInteger<int>(s, "index");
      shard.count = GetInteger<int>(s, "count");
      const json& run = s.at("run_frames");
      shard.run_first_frame = run.at("first").get<int64_t>();
      shard.run_last_frame = run.at("last").get<int64_t>();
      shard.run_frame_count = run.at("count").get<int64_t>();
      h.provenance.shard = shard;
    }
    for (const json& c : j.at("classes"))
      h.classes.push_back({GetInteger<uint32_t>(c, "id"), c.at("name").get<std::string>()});
    for (const json& l : j.at("layers")) h.layers.push_back(LayerFromJson(l));
    for (const json& m : j.at("metadata")) {
      CheckInsideReference(m.at("file").get<std::string>(),
                           file,
                           "/metadata/" + std::to_string(h.metadata.size()) + "/file");
      h.metadata.push_back({m.at("file").get<std::string>(),
                            m.at("perturbed").get<bool>(),
                            m.value("description", "")});
    }
    h.frame_count = j.at("frame_count").get<int64_t>();
    if (j.contains("rig")) h.rig = RigFromJson(j.at("rig"));
    return 0;
  });
  const json& c = j.at("conventions");
  Location where{file};
  where.json_pointer = "/conventions";
  try {
    h.conventions.world = WorldFrame::Make(c.at("world_frame").get<std::string>(),
                                           c.at("length_unit").get<std::string>());
  } catch (const Error& e) {
    throw Error(e.message(), where);
  }
  if (c.contains("geo_origin")) {
    const json& g = c.at("geo_origin");
    h.conventions.geo_origin = GeoOrigin{g.at("latitude_deg").get<double>(),
                                         g.at("longitude_deg").get<double>(),
                                         g.at("altitude_m").get<double>()};
  }
  const std::string handedness = h.conventions.world.right_handed() ? "right" : "left";
  if (c.at("handedness").get<std::string>() != handedness) {
    where.json_pointer = "/conventions/handedness";
    throw Error("world frame '" + h.conventions.world.name + "' is " + handedness + "-handed",
                where);
  }
  // Ids must be unique; layer names too.
  for (size_t a = 0; a < h.classes.size(); ++a) {
    for (size_t b = 0; b < a; ++b) {
      if (h.classes[a].id == h.classes[b].id) {
        where.json_pointer = "/classes/" + std::to_string(a) + "/id";
        throw Error("duplicate class id " + std::to_string(h.classes[a].id), where);
      }
    }
  }
  for (size_t a = 0; a < h.layers.size(); ++a) {
    for (size_t b = 0; b < a; ++b) {
      if (h.layers[a].name == h.layers[b].name) {
        where.json_pointer = "/layers/" + std::to_string(a) + "/name";
        throw Error("duplicate layer '" + h.layers[a].name + "'", where);
      }
    }
  }
  return h;
}

json FrameToJson(const Frame& f) {
  json objects = json::array();
  for (const ObjectTruth& o : f.objects) objects.push_back(ObjectToJson(o));
  json j = {{"index", f.index},
            {"time", f.time},
            {"camera", CameraToJson(f.camera)},
            {"files", f.files},
            {"objects", objects}};
  if (!f.sequence.empty()) j["sequence"] = f.sequence;
  if (f.shot) j["shot"] = *f.shot;
  if (!f.scene.is_null()) j["scene"] = f.scene;
  if (!f.exposure.is_null()) j["exposure"] = f.exposure;
  if (f.camera_velocity) j["camera_velocity"] = Vector3ToJson(*f.camera_velocity);
  if (f.rig_camera) j["rig_camera"] = *f.rig_camera;
  if (f.step) j["step"] = *f.step;
  if (!f.requirements.is_null()) j["requirements"] = f.requirements;
  return j;
}

Frame FrameFromJson(const json& j, const std::string& file, const std::string& pointer) {
  return AtPointer(file, pointer, [&] {
    Frame f;
    f.index = j.at("index").get<int64_t>();
    f.time = j.at("time").get<double>();
    f.sequence = j.value("sequence", "");
    if (j.contains("shot")) f.shot = j.at("shot").get<int64_t>();
    if (j.contains("scene")) f.scene = j.at("scene");
    if (j.contains("exposure")) f.exposure = j.at("exposure");
    if (j.contains("camera_velocity")) f.camera_velocity = Vector3FromJson(j.at("camera_velocity"));
    if (j.contains("rig_camera")) f.rig_camera = j.at("rig_camera").get<std::string>();
    if (j.contains("step")) f.step = j.at("step").get<int64_t>();
    if (j.contains("requirements")) f.requirements = j.at("requirements");
    f.camera = CameraFromJson(j.at("camera"));
    f.files = j.at("files").get<std::map<std::string, std::string>>();
    for (const auto& [layer, reference] : f.files)
      CheckInsideReference(reference, file, pointer + "/files/" + layer);
    for (const json& o : j.at("objects")) f.objects.push_back(ObjectFromJson(o));
    return f;
  });
}

json MetadataHeaderToJson(const MetadataHeader& h) {
  json j = {{"format", kMetadataFormat},
            {"format_version", h.format_version},
            {"perturbed", h.perturbed},
            {"frame_count", h.frame_count},
            {"frames", json::array()}};
  if (!h.source.empty()) j["source"] = h.source;
  if (h.noise) {
    j["noise"] = {
        {"model", h.noise->model}, {"parameters", h.noise->parameters}, {"seed", h.noise->seed}};
  }
  return j;
}

json MetadataFrameToJson(const MetadataFrame& f) {
  json j = {{"index", f.index},
            {"time", f.time},
            {"position", Vector3ToJson(f.position)},
            {"attitude",
             {{"roll", f.attitude.roll_deg},
              {"pitch", f.attitude.pitch_deg},
              {"yaw", f.attitude.yaw_deg}}},
            {"camera",
             {{"width", f.camera.width},
              {"height", f.camera.height},
              {"fx", f.camera.fx},
              {"fy", f.camera.fy},
              {"cx", f.camera.cx},
              {"cy", f.camera.cy}}}};
  if (!f.error.is_null()) j["error"] = f.error;
  if (f.geo)
    j["geo"] = {{"latitude_deg", f.geo->latitude_deg},
                {"longitude_deg", f.geo->longitude_deg},
                {"altitude_msl_m", f.geo->altitude_msl_m}};
  if (f.altitude_agl_m) j["altitude_agl_m"] = *f.altitude_agl_m;
  if (f.gsd_m) j["gsd_m"] = *f.gsd_m;
  if (!f.footprint.empty()) {
    json corners = json::array();
    for (const Eigen::Vector3d& c : f.footprint) corners.push_back(Vector3ToJson(c));
    j["footprint"] = corners;
  }
  return j;
}

MetadataHeader MetadataHeaderFromJson(const json& j, const std::string& file) {
  return AtPointer(file, "", [&] {
    MetadataHeader h;
    h.format_version = j.at("format_version").get<std::string>();
    h.perturbed = j.at("perturbed").get<bool>();
    h.source = j.value("source", "");
    h.frame_count = j.at("frame_count").get<int64_t>();
    if (j.contains("noise")) {
      const json& n = j.at("noise");
      h.noise = NoiseRecord{
          n.at("model").get<std::string>(), n.at("parameters"), GetInteger<uint64_t>(n, "seed")};
    }
    return h;
  });
}

MetadataFrame MetadataFrameFromJson(const json& j,
                                    const std::string& file,
                                    const std::string& pointer) {
  return AtPointer(file, pointer, [&] {
    MetadataFrame f;
    f.index = j.at("index").get<int64_t>();
    f.time = j.at("time").get<double>();
    f.position = Vector3FromJson(j.at("position"));
    const json& a = j.at("attitude");
    f.attitude = {
        a.at("roll").get<double>(), a.at("pitch").get<double>(), a.at("yaw").get<double>()};
    const json& c = j.at("camera");
    f.camera.width = GetInteger<int>(c, "width");
    f.camera.height = GetInteger<int>(c, "height");
    f.camera.fx = c.at("fx").get<double>();
    f.camera.fy = c.at("fy").get<double>();
    f.camera.cx = c.at("cx").get<double>();
    f.camera.cy = c.at("cy").get<double>();
    f.error = j.value("error", json());
    if (j.contains("geo")) {
      const json& g = j.at("geo");
      f.geo = Geodetic{g.at("latitude_deg").get<double>(),
                       g.at("longitude_deg").get<double>(),
                       g.at("altitude_msl_m").get<double>()};
    }
    if (j.contains("altitude_agl_m")) f.altitude_agl_m = j.at("altitude_agl_m").get<double>();
    if (j.contains("gsd_m")) f.gsd_m = j.at("gsd_m").get<double>();
    if (j.contains("footprint"))
      for (const json& c : j.at("footprint")) f.footprint.push_back(Vector3FromJson(c));
    return f;
  });
}

MetadataFrame TruthMetadata(const Frame& frame, const WorldFrame& world) {
  MetadataFrame m;
  m.index = frame.index;
  m.time = frame.time;
  m.camera = frame.camera.intrinsics;
  const Rigid3d cam_from_enu = world.CamFromEnuMetres(frame.camera.cam_from_world_rotation,
                                                      frame.camera.cam_from_world_translation);
  Eigen::Vector3d position_in_enu;
  PositionAndAttitudeFromCamFromEnu(cam_from_enu, &position_in_enu, &m.attitude);
  m.position = world.WorldFromEnuMetres(position_in_enu);
  return m;
}

}  // namespace lsds
