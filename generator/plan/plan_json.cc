#include "generator/plan/plan_json.h"

#include "libs/collection/json_io.h"
#include "libs/collection/schema.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"

namespace lsds {
namespace {

using nlohmann::json;

json Vec3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json Vec2(const Eigen::Vector2d& v) { return json::array({v.x(), v.y()}); }
json Mat3(const Eigen::Matrix3d& m) {
  json rows = json::array();
  for (int r = 0; r < 3; ++r) rows.push_back(json::array({m(r, 0), m(r, 1), m(r, 2)}));
  return rows;
}
Eigen::Vector3d ToVec3(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}
Eigen::Vector2d ToVec2(const json& j) { return {j.at(0).get<double>(), j.at(1).get<double>()}; }
Eigen::Matrix3d ToMat3(const json& j) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = j.at(r).at(c).get<double>();
  return m;
}

json CameraJson(const PinholeCamera& c) {
  return {{"width", c.width},
          {"height", c.height},
          {"fx", c.fx},
          {"fy", c.fy},
          {"cx", c.cx},
          {"cy", c.cy}};
}
PinholeCamera CameraFrom(const json& j) {
  PinholeCamera c;
  c.width = GetInteger<int>(j, "width");
  c.height = GetInteger<int>(j, "height");
  c.fx = j.at("fx").get<double>();
  c.fy = j.at("fy").get<double>();
  c.cx = j.at("cx").get<double>();
  c.cy = j.at("cy").get<double>();
  return c;
}

json ChangeJson(const ObjectChange& c) {
  json j = {{"object", c.object}};
  if (c.position) j["position"] = Vec3(*c.position);
  if (c.world_from_object) j["rotation"] = Mat3(*c.world_from_object);
  if (c.extent) j["extent"] = Vec3(*c.extent);
  if (c.material) j["material"] = *c.material;
  if (c.visible) j["visible"] = *c.visible;
  if (c.asset) j["asset"] = *c.asset;
  if (c.class_id) j["class_id"] = *c.class_id;
  if (c.velocity) j["velocity"] = Vec3(*c.velocity);
  return j;
}
ObjectChange ChangeFrom(const json& j) {
  ObjectChange c;
  c.object = j.at("object").get<std::string>();
  if (j.contains("position")) c.position = ToVec3(j["position"]);
  if (j.contains("rotation")) c.world_from_object = ToMat3(j["rotation"]);
  if (j.contains("extent")) c.extent = ToVec3(j["extent"]);
  if (j.contains("material")) c.material = j["material"].get<std::string>();
  if (j.contains("visible")) c.visible = j["visible"].get<bool>();
  if (j.contains("asset")) c.asset = j["asset"].get<std::string>();
  if (j.contains("class_id")) c.class_id = j["class_id"].get<uint32_t>();
  if (j.contains("velocity")) c.velocity = ToVec3(j["velocity"]);
  return c;
}

}  // namespace

json ObjectChangeToJson(const ObjectChange& change) { return ChangeJson(change); }

json ExposureToJson(const PlannedExposure& e) {
  json j = {{"mode", e.Manual() ? "manual" : "auto"}, {"compensation_ev", e.compensation_ev}};
  if (e.ev100) j["ev100"] = *e.ev100;
  if (e.shutter_s) j["shutter_s"] = *e.shutter_s;
  if (e.f_number) j["f_number"] = *e.f_number;
  if (e.iso) j["iso"] = *e.iso;
  if (e.focus_distance_m) j["focus_distance_m"] = *e.focus_distance_m;
  if (e.sensor_width_mm) j["sensor_width_mm"] = *e.sensor_width_mm;
  return j;
}

PlannedExposure ExposureFromJson(const json& j) {
  PlannedExposure e;
  auto get = [&j](const char* key) {
    return j.contains(key) ? std::optional<double>(j.at(key).get<double>()) : std::nullopt;
  };
  e.ev100 = get("ev100");
  e.shutter_s = get("shutter_s");
  e.f_number = get("f_number");
  e.iso = get("iso");
  e.focus_distance_m = get("focus_distance_m");
  e.sensor_width_mm = get("sensor_width_mm");
  e.compensation_ev = j.value("compensation_ev", 0.0);
  return e;
}

json SunJson(const PlannedSun& sun) {
  json j = {{"elevation_deg", sun.elevation_deg},
            {"azimuth_deg", sun.azimuth_deg},
            {"illuminance_lux", sun.illuminance_lux}};
  if (sun.clock_utc_s) {
    j["clock_utc_s"] = *sun.clock_utc_s;
    j["utc_offset_h"] = sun.utc_offset_h;
  }
  return j;
}

// The environment members, as the plan's top level writes them.
json EnvironmentJson(const PlannedEnvironment& e) {
  json j = {{"sky",
             {{"color", Vec3(e.sky.color)},
              {"cloud_type", e.sky.cloud_type},
              {"cloud_density", e.sky.cloud_density},
              {"luminance_cd_m2", e.sky.luminance_cd_m2}}},
            {"sun", SunJson(e.sun)},
            {"fog_density", e.fog_density},
            {"skylight_intensity", e.skylight_intensity},
            {"terrain_material", e.terrain_material}};
  // A terrain shape change (written only when there is one: older plans read as before).
  if (!e.terrain_shape.empty()) {
    json& shape = j["terrain_shape"] = json::object();
    if (e.terrain_shape.perlin_amplitude)
      shape["perlin_amplitude"] = *e.terrain_shape.perlin_amplitude;
    if (e.terrain_shape.perlin_frequency)
      shape["perlin_frequency"] = *e.terrain_shape.perlin_frequency;
  }
  return j;
}

PlannedEnvironment EnvironmentFromJson(const json& j) {
  PlannedEnvironment e;
  const json& sky = j.at("sky");
  e.sky.color = ToVec3(sky.at("color"));
  e.sky.cloud_type = sky.at("cloud_type").get<std::string>();
  e.sky.cloud_density = sky.at("cloud_density").get<double>();
  // Plans written before the photometric units: the unitless scales
  // (kLegacyNitsPerUnit).
  e.sky.luminance_cd_m2 =
      sky.contains("luminance_cd_m2")
          ? sky.at("luminance_cd_m2").get<double>()
          : sky.at("intensity").get<double>() * RelativeLuminance(e.sky.color) * kLegacyNitsPerUnit;
  const json& sun = j.at("sun");
  e.sun.elevation_deg = sun.at("elevation_deg").get<double>();
  e.sun.azimuth_deg = sun.at("azimuth_deg").get<double>();
  e.sun.illuminance_lux = sun.contains("illuminance_lux")
                              ? sun.at("illuminance_lux").get<double>()
                              : SunLuxFromIntensity(sun.at("intensity").get<double>());
  if (sun.contains("clock_utc_s")) {
    e.sun.clock_utc_s = sun.at("clock_utc_s").get<double>();
    e.sun.utc_offset_h = sun.value("utc_offset_h", 0.0);
  }
  e.fog_density = j.at("fog_density").get<double>();
  e.skylight_intensity = j.at("skylight_intensity").get<double>();
  e.terrain_material = j.value("terrain_material", std::string());
  if (j.contains("terrain_shape")) {
    const json& shape = j.at("terrain_shape");
    if (shape.contains("perlin_amplitude"))
      e.terrain_shape.perlin_amplitude = shape.at("perlin_amplitude").get<double>();
    if (shape.contains("perlin_frequency"))
      e.terrain_shape.perlin_frequency = shape.at("perlin_frequency").get<double>();
  }
  return e;
}

json PlannedFrameToJson(const PlannedFrame& f) {
  json changes = json::array();
  for (const ObjectChange& c : f.changes) changes.push_back(ChangeJson(c));
  json j = {{"index", f.index},
            {"time", f.time},
            {"sequence", f.sequence},
            {"shot", f.shot},
            {"camera", CameraJson(f.camera)},
            {"cam_from_world",
             {{"rotation", Mat3(f.cam_from_world.rotation.toRotationMatrix())},
              {"translation", Vec3(f.cam_from_world.translation)}}},
            {"changes", changes}};
  if (f.environment) j["environment"] = EnvironmentJson(*f.environment);
  if (f.camera_velocity) j["camera_velocity"] = Vec3(*f.camera_velocity);
  if (f.rig_camera) j["rig_camera"] = *f.rig_camera;
  if (f.step >= 0) j["step"] = f.step;
  if (f.requirements) j["requirements"] = *f.requirements;
  return j;
}

PlannedFrame PlannedFrameFromJson(const json& j,
                                  const std::string& file,
                                  const std::string& pointer) {
  try {
    PlannedFrame f;
    f.index = j.at("index").get<int64_t>();
    f.time = j.at("time").get<double>();
    f.sequence = j.at("sequence").get<std::string>();
    f.shot = j.value("shot", int64_t{-1});  // older plans: see PlanFromJson
    f.camera = CameraFrom(j.at("camera"));
    f.cam_from_world.rotation = Eigen::Quaterniond(ToMat3(j.at("cam_from_world").at("rotation")));
    f.cam_from_world.rotation.normalize();
    f.cam_from_world.translation = ToVec3(j.at("cam_from_world").at("translation"));
    for (const json& c : j.at("changes")) f.changes.push_back(ChangeFrom(c));
    if (j.contains("environment")) f.environment = EnvironmentFromJson(j.at("environment"));
    if (j.contains("camera_velocity")) f.camera_velocity = ToVec3(j.at("camera_velocity"));
    if (j.contains("rig_camera")) f.rig_camera = j.at("rig_camera").get<std::string>();
    f.step = j.value("step", int64_t{-1});
    if (j.contains("requirements")) f.requirements = j.at("requirements");
    return f;
  } catch (const json::exception& e) {
    throw Error(std::string("bad plan frame: ") + e.what(), Location(file, pointer));
  }
}

json PlanToJson(const Plan& plan) {
  json classes = json::array();
  for (const ClassInfo& c : plan.classes) classes.push_back({{"id", c.id}, {"name", c.name}});
  json objects = json::array();
  for (const PlannedObject& o : plan.objects) {
    objects.push_back({{"name", o.name},
                       {"symbol", o.symbol},
                       {"class", o.class_name},
                       {"class_id", o.class_id},
                       {"instance_id", o.instance_id},
                       {"visible", o.visible},
                       {"target", o.target},
                       {"position", Vec3(o.position)},
                       {"rotation", Mat3(o.world_from_object)},
                       {"extent", Vec3(o.extent)},
                       {"material", o.material}});
  }
  json frames = json::array();
  for (const PlannedFrame& f : plan.frames) frames.push_back(PlannedFrameToJson(f));
  const PlannedTerrain& t = plan.terrain;
  json environment = EnvironmentJson(EnvironmentOf(plan));
  environment.erase("terrain_material");  // the terrain's own "material"
  json j = {{"format", kPlanFormat},
            {"format_version", kPlanFormatVersion},
            {"seed", plan.seed},
            {"scene_source", plan.scene_source},
            {"capture_source", plan.capture_source},
            {"classes", classes},
            {"terrain",
             {{"present", t.present},
              {"size", Vec2(t.size)},
              {"perlin_amplitude", t.perlin_amplitude},
              {"perlin_frequency", t.perlin_frequency},
              {"perlin_seed", t.perlin_seed},
              {"material", t.material},
              {"class_id", t.class_id},
              {"instance_id", t.instance_id}}},
            {"objects", objects},
            {"post_process", plan.post_process},
            {"capture_settings", plan.capture_settings},
            {"exposure", ExposureToJson(plan.exposure)},
            {"frame_count", plan.frames.size()},
            {"frames", frames}};
  j.update(environment);
  if (t.vegetation.density > 0)  // absent without: plans from before keep their bytes
    j["terrain"]["vegetation"] = {{"density", t.vegetation.density},
                                  {"kind", t.vegetation.kind},
                                  {"height_m", t.vegetation.height_m},
                                  {"seed", t.vegetation.seed}};
  if (!plan.requirements.is_null()) j["requirements"] = plan.requirements;
  if (plan.geo)
    j["geo"] = {{"latitude_deg", plan.geo->latitude_deg},
                {"longitude_deg", plan.geo->longitude_deg},
                {"altitude_m", plan.geo->altitude_m}};
  if (plan.rig) j["rig"] = RigToJson(*plan.rig);
  return j;
}

Plan PlanFromJson(const json& j, const std::string& file) {
  JsonSchema::Get("plan.schema.json").ValidateOrThrow(j, file);
  try {
    Plan plan;
    plan.seed = GetInteger<uint64_t>(j, "seed");
    plan.scene_source = j.at("scene_source").get<std::string>();
    plan.capture_source = j.at("capture_source").get<std::string>();
    for (const json& c : j.at("classes"))
      plan.classes.push_back({GetInteger<uint32_t>(c, "id"), c.at("name").get<std::string>()});
    PlannedEnvironment environment = EnvironmentFromJson(j);
    const json& t = j.at("terrain");
    plan.terrain.present = t.at("present").get<bool>();
    plan.terrain.size = ToVec2(t.at("size"));
    plan.terrain.perlin_amplitude = t.at("perlin_amplitude").get<double>();
    plan.terrain.perlin_frequency = t.at("perlin_frequency").get<double>();
    plan.terrain.perlin_seed = GetInteger<uint64_t>(t, "perlin_seed");
    plan.terrain.material = t.at("material").get<std::string>();
    environment.terrain_material = plan.terrain.material;
    SetEnvironment(environment, &plan);
    if (j.contains("geo")) {
      const json& g = j.at("geo");
      plan.geo = GeoOrigin{g.at("latitude_deg").get<double>(),
                           g.at("longitude_deg").get<double>(),
                           g.at("altitude_m").get<double>()};
    }
    plan.terrain.class_id = GetInteger<uint32_t>(t, "class_id");
    plan.terrain.instance_id = GetInteger<uint32_t>(t, "instance_id");
    if (t.contains("vegetation")) {
      const json& v = t.at("vegetation");
      plan.terrain.vegetation.density = v.at("density").get<double>();
      plan.terrain.vegetation.kind = v.at("kind").get<std::string>();
      plan.terrain.vegetation.height_m = v.at("height_m").get<double>();
      plan.terrain.vegetation.seed = GetInteger<uint64_t>(v, "seed");
    }
    for (const json& o : j.at("objects")) {
      PlannedObject p;
      p.name = o.at("name").get<std::string>();
      p.symbol = o.at("symbol").get<std::string>();
      p.class_name = o.at("class").get<std::string>();
      p.class_id = GetInteger<uint32_t>(o, "class_id");
      p.instance_id = GetInteger<uint32_t>(o, "instance_id");
      p.visible = o.at("visible").get<bool>();
      p.target = o.at("target").get<bool>();
      p.position = ToVec3(o.at("position"));
      p.world_from_object = ToMat3(o.at("rotation"));
      p.extent = ToVec3(o.at("extent"));
      p.material = o.at("material").get<std::string>();
      plan.objects.push_back(p);
    }
    plan.post_process = j.at("post_process").get<std::vector<std::string>>();
    if (j.contains("capture_settings")) plan.capture_settings = j["capture_settings"];
    if (j.contains("exposure")) plan.exposure = ExposureFromJson(j["exposure"]);
    if (j.contains("rig")) plan.rig = RigFromJson(j.at("rig"));
    if (j.contains("requirements")) plan.requirements = j["requirements"];
    const json& frames = j.at("frames");
    for (size_t i = 0; i < frames.size(); ++i)
      plan.frames.push_back(PlannedFrameFromJson(frames[i], file, "/frames/" + std::to_string(i)));
    // Plans written before shots existed: a shot is a run of consecutive
    // frames of one sequence.
    for (size_t i = 0; i < plan.frames.size(); ++i) {
      PlannedFrame& f = plan.frames[i];
      if (f.shot >= 0) continue;
      const PlannedFrame* p = i > 0 ? &plan.frames[i - 1] : nullptr;
      f.shot = p && p->sequence == f.sequence && p->index + 1 == f.index ? p->shot : f.index;
    }
    return plan;
  } catch (const json::exception& e) {
    throw Error(std::string("bad plan: ") + e.what(), Location(file, ""));
  }
}

}  // namespace lsds
