// A camera of AirSim's settings.json as AirSim itself builds it
// (docs/import.md, "AirSim"): the pawn's own camera, then `CameraDefaults`,
// then the vehicle's `Cameras.<name>` entry, each overriding only the keys it
// lists (AirLib/include/common/AirSimSettings.hpp, createCameraSetting and
// loadCaptureSettings).
#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace lsds::import {

// A camera's mount on the vehicle (settings.json Vehicles.V.Cameras.C): X, Y,
// Z in metres in the body frame (FRD: forward, right, down), Roll, Pitch, Yaw
// in degrees; body_from_camera = Rz(yaw) * Ry(pitch) * Rx(roll), the camera
// frame FRD with x along the optical axis.
struct AirSimMount {
  Eigen::Vector3d position_in_body = Eigen::Vector3d::Zero();
  double roll = 0, pitch = 0, yaw = 0;
  Eigen::Matrix3d BodyFromCamera() const;
};

// One image type's capture (CaptureSettings entry): its size and horizontal
// FOV (AirSimSettings.hpp CaptureSetting; FOV 90 when unset, PIPCamera's).
struct AirSimCapture {
  int width = 256, height = 144;
  double fov_deg = 90;
  bool operator==(const AirSimCapture& o) const {
    return width == o.width && height == o.height && fov_deg == o.fov_deg;
  }
};

// The camera's gimbal (settings.json `Gimbal`, AirSimSettings.hpp GimbalSetting
// and createGimbalSetting): `Stabilization` in [0, 1] (0: none) and the
// world-frame Pitch, Roll, Yaw in degrees it holds (NaN: not held).
struct AirSimGimbal {
  double stabilization = 0;
  double roll = std::numeric_limits<double>::quiet_NaN();
  double pitch = std::numeric_limits<double>::quiet_NaN();
  double yaw = std::numeric_limits<double>::quiet_NaN();
  // The camera's world rotation (NED from the FRD camera frame) as the gimbal
  // holds it: APIPCamera::Tick sets each held Euler angle (yaw, pitch, roll of
  // Unreal's FRotator, the same Rz Ry Rx as the mount) to
  // held * s + current * (1 - s), whose fixed point for a body at rest is the
  // held angle whatever s > 0 is; the angles not held stay.
  Eigen::Matrix3d Held(const Eigen::Matrix3d& ned_from_camera) const;
};

// What the import needs of one camera: its mount, its gimbal and its captures.
struct AirSimCamera {
  AirSimMount mount;
  AirSimGimbal gimbal;
  // The Scene capture (ImageType 0), the camera of the collection.
  int width = 256, height = 144;  // CaptureSetting's defaults
  double fov_deg = 90;            // PIPCamera's when FOV_Degrees is not set
  // Every image type's capture by ImageType (0 Scene, 1 DepthPlanar, 2
  // DepthPerspective, 5 Segmentation, ...); a type no entry lists has the
  // defaults (256 x 144, FOV 90).
  std::map<int, AirSimCapture> captures;
  AirSimCapture CaptureOf(int image_type) const;
  // Where each value came from, for the collection's provenance.
  std::string mount_origin, capture_origin;
};

// The camera `camera` of vehicle `vehicle` from the parsed settings.json
// `settings` (read from `file`, for locations; an empty object gives AirSim's
// defaults). Throws lsds::Error at the JSON pointer of a malformed value, or
// when the camera is neither in the vehicle's Cameras nor one of the pawn's
// own cameras.
AirSimCamera ResolveAirSimCamera(const nlohmann::json& settings,
                                 const std::string& file,
                                 const std::string& vehicle,
                                 const std::string& camera);

}  // namespace lsds::import
