#include "importers/airsim/airsim_settings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "importers/source_json.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::import {

using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
double Rad(double deg) { return deg * kPi / 180.0; }

// A camera pose with NaN for "not set", as AirSimSettings.hpp keeps it
// (CameraSetting: "nan means keep the default values set in components").
struct PoseKeys {
  double x = kNaN, y = kNaN, z = kNaN, roll = kNaN, pitch = kNaN, yaw = kNaN;
};

struct Capture {
  int width = 256, height = 144;  // AirSimSettings.hpp CaptureSetting
  double fov_deg = kNaN;          // NaN: the component's own (90)
};

// A pawn's own cameras: name (and the legacy ids "0".."4", "" and "fpv"
// that getCameras() maps onto them) -> mount in the body frame (NED metres,
// degrees). Multirotors and the ComputerVision pawn
// (Vehicles/ComputerVision/ComputerVisionPawn.cpp: bases at the root, front
// left/right 12.5 cm aside, bottom_center spawned at FRotator(-90, 0, 0),
// back_center at FRotator(0, -180, 0); FlyingPawn.cpp maps the same names);
// cars (Vehicles/Car/CarPawn.cpp: bases relative to the car's mesh, Unreal
// cm x forward, y right, z up).
struct PawnCamera {
  const char* names[3];
  PoseKeys pose;
};

const std::vector<PawnCamera>& PawnCameras(bool car) {
  static const std::vector<PawnCamera> multirotor = {
      {{"front_center", "0", ""}, {0, 0, 0, 0, 0, 0}},
      {{"fpv", nullptr, nullptr}, {0, 0, 0, 0, 0, 0}},
      {{"front_right", "1", nullptr}, {0, 0.125, 0, 0, 0, 0}},
      {{"front_left", "2", nullptr}, {0, -0.125, 0, 0, 0, 0}},
      {{"bottom_center", "3", nullptr}, {0, 0, 0, 0, -90, 0}},
      {{"back_center", "4", nullptr}, {0, 0, 0, 0, 0, -180}}};
  static const std::vector<PawnCamera> cars = {
      {{"front_center", "0", ""}, {2, 0, -1, 0, 0, 0}},
      {{"front_right", "1", nullptr}, {2, 0.125, -1, 0, 0, 0}},
      {{"front_left", "2", nullptr}, {2, -0.125, -1, 0, 0, 0}},
      {{"fpv", "3", nullptr}, {0, -0.25, -1.25, 0, 0, 0}},
      {{"back_center", "4", nullptr}, {-2, 0, -1, 0, 0, -180}}};
  return car ? cars : multirotor;
}

std::optional<PoseKeys> PawnPose(bool car, const std::string& camera) {
  for (const PawnCamera& entry : PawnCameras(car))
    for (const char* name : entry.names)
      if (name != nullptr && camera == name) return entry.pose;
  return std::nullopt;
}

std::string PawnCameraNames(bool car) {
  std::vector<std::string> names;
  for (const PawnCamera& entry : PawnCameras(car))
    for (const char* name : entry.names)
      if (name != nullptr) names.push_back(name[0] == '\0' ? "\"\"" : name);
  return Join(names, ", ");
}

double NumberAt(const json& object,
                const char* key,
                double fallback,
                const std::string& file,
                const std::string& where) {
  if (!object.contains(key)) return fallback;
  const json& value = object.at(key);
  if (!value.is_number())
    throw Error(std::string("'") + key + "' must be a number, not " + ValueText(value),
                Location(file, where + "/" + key));
  return value.get<double>();
}

// createVectorSetting / createRotationSetting: each key overrides its default.
PoseKeys ReadPose(const json& camera,
                  PoseKeys pose,
                  const std::string& file,
                  const std::string& where) {
  pose.x = NumberAt(camera, "X", pose.x, file, where);
  pose.y = NumberAt(camera, "Y", pose.y, file, where);
  pose.z = NumberAt(camera, "Z", pose.z, file, where);
  pose.roll = NumberAt(camera, "Roll", pose.roll, file, where);
  pose.pitch = NumberAt(camera, "Pitch", pose.pitch, file, where);
  pose.yaw = NumberAt(camera, "Yaw", pose.yaw, file, where);
  return pose;
}

// loadCaptureSettings (AirSimSettings.hpp 721-737): each entry replaces the
// capture of its ImageType with a fresh CaptureSetting (defaults 256 x 144,
// FOV unset), so a capture of CameraDefaults is not merged key by key into a
// camera's own entry of the same type; types the entry does not list keep
// theirs.
void ReadCaptures(const json& camera,
                  const std::string& file,
                  const std::string& where,
                  std::map<int, Capture>* by_type) {
  if (!camera.contains("CaptureSettings")) return;
  const json& captures = camera.at("CaptureSettings");
  if (!captures.is_array())
    throw Error("'CaptureSettings' must be an array", Location(file, where + "/CaptureSettings"));
  for (size_t i = 0; i < captures.size(); ++i) {
    const json& entry = captures.at(i);
    const std::string at = where + "/CaptureSettings/" + std::to_string(i);
    if (!entry.is_object()) throw Error("expected an object", Location(file, at));
    const int type = IntegerAt<int>(entry.value("ImageType", json(0)), file, at + "/ImageType");
    Capture capture;
    capture.width =
        IntegerAt<int>(entry.value("Width", json(capture.width)), file, at + "/Width", 1);
    capture.height =
        IntegerAt<int>(entry.value("Height", json(capture.height)), file, at + "/Height", 1);
    capture.fov_deg = NumberAt(entry, "FOV_Degrees", capture.fov_deg, file, at);
    if (!std::isnan(capture.fov_deg) && !(capture.fov_deg > 0 && capture.fov_deg < 180))
      throw Error("FOV_Degrees must be in (0, 180)", Location(file, at + "/FOV_Degrees"));
    (*by_type)[type] = capture;
  }
}

// createGimbalSetting (AirSimSettings.hpp 1033-1040): a `Gimbal` object
// replaces the whole gimbal, Stabilization 0 and angles unset unless listed.
std::optional<AirSimGimbal> ReadGimbal(const json& camera,
                                       const std::string& file,
                                       const std::string& where) {
  if (!camera.contains("Gimbal")) return std::nullopt;
  const json& entry = camera.at("Gimbal");
  const std::string at = where + "/Gimbal";
  if (!entry.is_object()) throw Error("expected an object", Location(file, at));
  AirSimGimbal gimbal;
  gimbal.stabilization = NumberAt(entry, "Stabilization", 0, file, at);
  gimbal.roll = NumberAt(entry, "Roll", kNaN, file, at);
  gimbal.pitch = NumberAt(entry, "Pitch", kNaN, file, at);
  gimbal.yaw = NumberAt(entry, "Yaw", kNaN, file, at);
  // APIPCamera::setupCameraFromSettings clips it to [0, 1].
  gimbal.stabilization = std::clamp(gimbal.stabilization, 0.0, 1.0);
  return gimbal;
}

}  // namespace

namespace {

Eigen::Matrix3d RotationOfYawPitchRoll(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(Rad(yaw), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(Rad(pitch), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(Rad(roll), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

Eigen::Matrix3d AirSimMount::BodyFromCamera() const {
  return RotationOfYawPitchRoll(yaw, pitch, roll);
}

Eigen::Matrix3d AirSimGimbal::Held(const Eigen::Matrix3d& ned_from_camera) const {
  if (!(stabilization > 0)) return ned_from_camera;
  // The Euler angles of Rz(yaw) Ry(pitch) Rx(roll), as Unreal's FRotator
  // decomposes a rotation (pitch in [-90, 90]).
  const Eigen::Matrix3d& r = ned_from_camera;
  const double deg = 180.0 / kPi;
  const double current_pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0)) * deg;
  double current_yaw = std::atan2(r(1, 0), r(0, 0)) * deg;
  double current_roll = std::atan2(r(2, 1), r(2, 2)) * deg;
  if (std::abs(r(2, 0)) > 1 - 1e-12) {
    // Looking straight up or down: yaw and roll turn about the same axis;
    // all of it is counted as yaw (any split recomposes to the same rotation;
    // it matters only for a gimbal holding one of yaw and roll, not both).
    current_yaw = std::atan2(-r(0, 1), r(1, 1)) * deg;
    current_roll = 0;
  }
  auto held = [](double angle, double current) { return std::isnan(angle) ? current : angle; };
  return RotationOfYawPitchRoll(
      held(yaw, current_yaw), held(pitch, current_pitch), held(roll, current_roll));
}

AirSimCapture AirSimCamera::CaptureOf(int image_type) const {
  const auto found = captures.find(image_type);
  return found == captures.end() ? AirSimCapture{} : found->second;
}

AirSimCamera ResolveAirSimCamera(const json& settings,
                                 const std::string& file,
                                 const std::string& vehicle,
                                 const std::string& camera) {
  if (!settings.is_object()) throw Error("settings must be a JSON object", Location(file));
  // The vehicle's entry; a vehicle absent from Vehicles has no camera of its
  // own (AirSim then creates it with the defaults of its SimMode).
  const std::string vehicle_at = "/Vehicles/" + vehicle;
  const json none = json::object();
  const json& vehicles = settings.contains("Vehicles") ? settings.at("Vehicles") : none;
  const json& vehicle_settings = vehicles.contains(vehicle) ? vehicles.at(vehicle) : none;
  if (!vehicle_settings.is_object()) throw Error("expected an object", Location(file, vehicle_at));
  const std::string type =
      vehicle_settings.contains("VehicleType")
          ? StringAt(vehicle_settings.at("VehicleType"), file, vehicle_at + "/VehicleType")
          : std::string();
  const bool car = type == "PhysXCar" || type == "ArduRover";
  const std::optional<PoseKeys> pawn = PawnPose(car, camera);

  // CameraDefaults (loadDefaultCameraSetting -> createCameraSetting).
  PoseKeys defaults_pose;
  std::map<int, Capture> captures;
  AirSimCamera result;
  if (settings.contains("CameraDefaults")) {
    const json& defaults = settings.at("CameraDefaults");
    if (!defaults.is_object()) throw Error("expected an object", Location(file, "/CameraDefaults"));
    defaults_pose = ReadPose(defaults, defaults_pose, file, "/CameraDefaults");
    ReadCaptures(defaults, file, "/CameraDefaults", &captures);
    if (auto gimbal = ReadGimbal(defaults, file, "/CameraDefaults")) result.gimbal = *gimbal;
  }

  PoseKeys pose;
  const json& cameras =
      vehicle_settings.contains("Cameras") ? vehicle_settings.at("Cameras") : none;
  const std::string camera_at = vehicle_at + "/Cameras/" + camera;
  if (cameras.is_object() && cameras.contains(camera)) {
    // A camera listed in Cameras is spawned anew at its settings' pose
    // (PawnSimApi::createCamerasFromSettings): its keys over CameraDefaults'.
    const json& entry = cameras.at(camera);
    if (!entry.is_object()) throw Error("expected an object", Location(file, camera_at));
    // createCameraSetting starts from a copy of CameraDefaults: its captures and gimbal stay
    // unless the camera lists its own.
    pose = ReadPose(entry, defaults_pose, file, camera_at);
    ReadCaptures(entry, file, camera_at, &captures);
    if (auto gimbal = ReadGimbal(entry, file, camera_at)) result.gimbal = *gimbal;
    result.mount_origin = "settings.json " + camera_at + " over /CameraDefaults";
    result.capture_origin = result.mount_origin;
  } else if (pawn) {
    // The pawn's own camera keeps its mount: APIPCamera::setupCameraFromSettings
    // applies CameraDefaults' captures and gimbal but not its position or rotation.
    pose = *pawn;
    result.mount_origin = "the pawn's own camera";
    result.capture_origin = "settings.json /CameraDefaults";
  } else {
    throw Error("camera '" + camera + "' is neither in the vehicle's Cameras nor a camera of the " +
                    (car ? "car" : "multirotor") + " pawn (" + PawnCameraNames(car) + ")",
                Location(file, vehicle_at + "/Cameras"));
  }
  // Keys left NaN keep the pawn camera's value (0 for a camera of its own).
  const PoseKeys base = pawn.value_or(PoseKeys{0, 0, 0, 0, 0, 0});
  auto kept = [](double value, double fallback) { return std::isnan(value) ? fallback : value; };
  result.mount.position_in_body = {
      kept(pose.x, base.x), kept(pose.y, base.y), kept(pose.z, base.z)};
  result.mount.roll = kept(pose.roll, base.roll);
  result.mount.pitch = kept(pose.pitch, base.pitch);
  result.mount.yaw = kept(pose.yaw, base.yaw);
  for (const auto& [image_type, capture] : captures)
    result.captures[image_type] = {capture.width, capture.height, kept(capture.fov_deg, 90.0)};
  const AirSimCapture scene = result.CaptureOf(0);
  result.width = scene.width;
  result.height = scene.height;
  result.fov_deg = scene.fov_deg;
  return result;
}

}  // namespace lsds::import
