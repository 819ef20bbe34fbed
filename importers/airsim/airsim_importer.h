// AirSim recordings (docs/import.md, "AirSim"): airsim_rec.txt (the vehicle's
// pose in the local NED frame, metres, and the images of each row), images/
// with the Scene PNG, a DepthPlanar or DepthPerspective PFM written top row
// first, and the Segmentation PNG (colours of the segmentation palette), the
// camera mount and capture settings from settings.json, and a sidecar
// lsds_objects.json mapping segmentation colours to instance and class ids and
// giving the objects' 3D boxes. Converted to ENU metres at import.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "importers/importer.h"
#include "libs/geometry/rigid3.h"
#include "libs/util/confined_path.h"

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

// The OpenCV cam_from_world pose (ENU metres) of the camera on a vehicle at
// `vehicle_in_ned` with orientation `ned_from_body`, and back.
Rigid3d CamFromEnuOfAirSim(const Eigen::Vector3d& vehicle_in_ned,
                           const Eigen::Quaterniond& ned_from_body,
                           const AirSimMount& mount);
void AirSimVehicleOfCamFromEnu(const Rigid3d& cam_from_enu,
                               const AirSimMount& mount,
                               Eigen::Vector3d* vehicle_in_ned,
                               Eigen::Quaterniond* ned_from_body);

class AirSimImporter : public Importer {
 public:
  std::string name() const override { return "airsim"; }
  SourceDescription Open(const std::filesystem::path& source,
                         const ImportOptions& options) override;
  SourceFrame ReadFrame(int64_t index) override;

 private:
  struct Row {
    int line = 0;
    double time = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    std::filesystem::path scene, depth, segmentation;
  };
  struct Labelled {
    uint32_t instance_id = 0, class_id = 0;
  };
  void ReadObjects(const std::filesystem::path& file);
  void ReadSettings(const std::filesystem::path& file);
  void ReadRecord(const std::filesystem::path& source);

  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::filesystem::path rec_file_;
  std::vector<Row> rows_;
  std::string vehicle_ = "Drone1", camera_ = "0";
  DepthKind depth_kind_ = DepthKind::kPlanar;
  double sky_depth_m_ = 1e4;
  std::map<std::array<uint8_t, 3>, Labelled> by_colour_;
  std::vector<ObjectIdentity> targets_;
  std::vector<ClassInfo> classes_;
  AirSimMount mount_;
  int width_ = 0, height_ = 0;
  double fov_deg_ = 90;
};

}  // namespace lsds::import
