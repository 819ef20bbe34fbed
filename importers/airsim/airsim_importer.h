// AirSim recordings (docs/import.md, "AirSim"): airsim_rec.txt (the vehicle's
// pose in the local NED frame, metres, and the images of each row), images/
// with the Scene PNG and, when recorded, a DepthPlanar or DepthPerspective PFM
// written top row first and the Segmentation PNG (colours of the segmentation
// palette); the camera mount and capture settings from settings.json as AirSim
// merges them (airsim_settings.h); an optional sidecar lsds_objects.json
// mapping segmentation colours to instance and class ids and giving the
// objects' 3D boxes. Converted to ENU metres at import.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "importers/airsim/airsim_settings.h"
#include "importers/importer.h"
#include "libs/geometry/rigid3.h"
#include "libs/util/confined_path.h"

namespace lsds::import {

// The OpenCV cam_from_world pose (ENU metres) of the camera on a vehicle at
// `vehicle_in_ned` with orientation `ned_from_body`, its world rotation held by
// `gimbal` where it has one, and back (without a gimbal).
Rigid3d CamFromEnuOfAirSim(const Eigen::Vector3d& vehicle_in_ned,
                           const Eigen::Quaterniond& ned_from_body,
                           const AirSimMount& mount,
                           const AirSimGimbal& gimbal = {});
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
  // The stages of ReadRecord for one row: its images of the camera by type (`where`: the
  // ImageFile cell), the passes of the recording (from the first row), the images the row
  // must hold (`where`: the row).
  std::map<int, std::filesystem::path> ImagesOfRow(const std::string& image_file_cell,
                                                   const std::filesystem::path& folder,
                                                   const Location& where) const;
  void ChoosePasses(const std::map<int, std::filesystem::path>& by_type);
  void AssignImages(const std::map<int, std::filesystem::path>& by_type,
                    const Location& where,
                    Row* row) const;
  // Vehicle and camera from the recording itself when there is no sidecar.
  void ChooseVehicleAndCamera(const std::filesystem::path& rec_file);
  void ReadDepth(const std::filesystem::path& path, int64_t index, SourceFrame* frame) const;
  void ReadSegmentation(const std::filesystem::path& path, SourceFrame* frame) const;
  cv::Mat ReadScenePng(const std::filesystem::path& path) const;
  // Whether `image_type` has the Scene's capture (size and FOV); else a warning says it is not
  // read.
  bool SharesSceneCapture(int image_type);

  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::filesystem::path rec_file_;
  std::vector<Row> rows_;
  std::string vehicle_ = "Drone1", camera_ = "0";
  bool has_sidecar_ = false;
  // Which passes the recording holds for the camera (from its first row;
  // every row must hold them), and which depth type was asked for.
  bool has_depth_ = false, has_segmentation_ = false;
  std::optional<DepthKind> asked_depth_;
  std::vector<std::string> warnings_;
  DepthKind depth_kind_ = DepthKind::kPlanar;
  double sky_depth_m_ = 1e4;
  std::map<std::array<uint8_t, 3>, Labelled> by_colour_;
  std::vector<ObjectIdentity> targets_;
  std::vector<ClassInfo> classes_;
  AirSimCamera camera_settings_;
};

}  // namespace lsds::import
