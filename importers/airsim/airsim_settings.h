// A camera of AirSim's settings.json as AirSim itself builds it
// (docs/import.md, "AirSim"): the pawn's own camera, then `CameraDefaults`,
// then the vehicle's `Cameras.<name>` entry, each overriding only the keys it
// lists (AirLib/include/common/AirSimSettings.hpp, createCameraSetting and
// loadCaptureSettings).
#pragma once

#include <filesystem>
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

// What the import needs of one camera: its mount and its Scene capture.
struct AirSimCamera {
  AirSimMount mount;
  int width = 256, height = 144;  // CaptureSetting's defaults
  double fov_deg = 90;            // PIPCamera's when FOV_Degrees is not set
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
