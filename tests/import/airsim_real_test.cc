// lsds import airsim on what AirSim really writes: settings merged as
// AirSimSettings.hpp merges them (CameraDefaults, a camera's own keys, the
// pawn's cameras), and a real PX4 recording with Scene images only
// (tests/import/data/airsim_px4, README there): accepted, valid, poses equal to
// the recording's rows.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "importers/airsim/airsim_settings.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

import::AirSimCamera Resolve(const json& settings, const std::string& camera){
    return import::ResolveAirSimCamera(settings, "settings.json", "Drone1", camera);
}  // namespace

TEST(AirSimSettings, CameraDefaultsSetTheCaptureOfEveryCamera) {
  // The issue's case: a FOV in CameraDefaults, a camera listed without one.
  const json settings = json::parse(R"({
    "CameraDefaults": {"CaptureSettings": [{"ImageType": 0, "Width": 256, "Height": 144,
                                            "FOV_Degrees": 60}]},
    "Vehicles": {"Drone1": {"VehicleType": "SimpleFlight",
                            "Cameras": {"down": {"Pitch": -90, "Z": 0.1}}}}})");
  const import::AirSimCamera down = Resolve(settings, "down");
  EXPECT_EQ(down.width, 256);
  EXPECT_EQ(down.height, 144);
  EXPECT_DOUBLE_EQ(down.fov_deg, 60);
  EXPECT_NEAR(128 / std::tan(down.fov_deg * kPi / 360), 221.7025033688163, 1e-9);
  EXPECT_DOUBLE_EQ(down.mount.pitch, -90);
  EXPECT_DOUBLE_EQ(down.mount.position_in_body.z(), 0.1);
  // A camera absent from Cameras (the default recording camera "") is the
  // pawn's front_center with CameraDefaults' capture.
  const import::AirSimCamera fallback = Resolve(settings, "");
  EXPECT_DOUBLE_EQ(fallback.fov_deg, 60);
  EXPECT_EQ(fallback.mount.position_in_body, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(fallback.mount.pitch, 0);
}

TEST(AirSimSettings, MissingMountKeysKeepThePawnCamerasMount) {
  // bottom_center listed only for its capture: AirSim keeps the pawn's
  // mount, pitched -90 (ComputerVisionPawn.cpp FRotator(-90, 0, 0)).
  const json settings = json::parse(R"({"Vehicles": {"Drone1": {"Cameras": {
      "bottom_center": {"CaptureSettings": [{"ImageType": 0, "Width": 640, "Height": 480}]},
      "back_center": {"Roll": 5}}}}})");
  const import::AirSimCamera bottom = Resolve(settings, "bottom_center");
  EXPECT_DOUBLE_EQ(bottom.mount.pitch, -90);
  EXPECT_DOUBLE_EQ(bottom.mount.yaw, 0);
  EXPECT_EQ(bottom.width, 640);
  EXPECT_EQ(bottom.height, 480);
  EXPECT_DOUBLE_EQ(bottom.fov_deg, 90);  // unset: the component's 90
  const import::AirSimCamera back = Resolve(settings, "back_center");
  EXPECT_DOUBLE_EQ(back.mount.yaw, -180);
  EXPECT_DOUBLE_EQ(back.mount.roll, 5);
  // The legacy id "3" is bottom_center too.
  EXPECT_DOUBLE_EQ(Resolve(json::object(), "3").mount.pitch, -90);
}

TEST(AirSimSettings, ACamerasOwnCaptureReplacesTheDefaultsCaptureOfItsType) {
  // loadCaptureSettings: an entry is a fresh CaptureSetting, so the FOV of
  // CameraDefaults does not carry into a camera's own Scene entry.
  const json settings = json::parse(R"({
    "CameraDefaults": {"X": 0.5, "CaptureSettings": [{"ImageType": 0, "FOV_Degrees": 60}]},
    "Vehicles": {"Drone1": {"Cameras": {
        "front_center": {"CaptureSettings": [{"ImageType": 0, "Width": 800}]}}}}})");
  const import::AirSimCamera front = Resolve(settings, "front_center");
  EXPECT_EQ(front.width, 800);
  EXPECT_EQ(front.height, 144);
  EXPECT_DOUBLE_EQ(front.fov_deg, 90);
  EXPECT_DOUBLE_EQ(front.mount.position_in_body.x(), 0.5);  // X from CameraDefaults
  // A pawn camera not listed keeps its own mount: CameraDefaults' X is not
  // applied to it (APIPCamera::setupCameraFromSettings sets captures only).
  EXPECT_DOUBLE_EQ(Resolve(settings, "front_left").mount.position_in_body.x(), 0);
  EXPECT_DOUBLE_EQ(Resolve(settings, "front_left").fov_deg, 60);
}

TEST(AirSimSettings, AnUnknownCameraOrAMalformedValueIsALocatedError) {
  try {
    Resolve(json::object(), "belly");
    FAIL() << "accepted an unknown camera";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/Vehicles/Drone1/Cameras"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("bottom_center"), std::string::npos) << e.what();
  }
  const json bad =
      json::parse(R"({"Vehicles": {"Drone1": {"Cameras": {"c": {"Pitch": "down"}}}}})");
  try {
    Resolve(bad, "c");
    FAIL() << "accepted a text pitch";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/Vehicles/Drone1/Cameras/c/Pitch"), std::string::npos)
        << e.what();
  }
}

// The real recording's rows: time, NED position, body quaternion (W, X, Y, Z).
struct RecordedRow {
  double ms = 0;
  Eigen::Vector3d ned = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

std::vector<RecordedRow> ReadRows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<RecordedRow> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = Split(line, '\t');
    RecordedRow row;
    row.ms = std::stod(cells[1]);
    row.ned = {std::stod(cells[2]), std::stod(cells[3]), std::stod(cells[4])};
    row.q = Eigen::Quaterniond(
        std::stod(cells[5]), std::stod(cells[6]), std::stod(cells[7]), std::stod(cells[8]));
    rows.push_back(row);
  }
  return rows;
}

// A copy of the real recording with the Scene PNGs its rows name.
fs::path CopyPx4Recording(const fs::path& dir) {
  const fs::path data = fs::path(SourceDir()) / "tests/import/data/airsim_px4";
  const fs::path source = dir / "2024-09-21-23-41-46";
  fs::create_directories(source / "images");
  fs::copy_file(data / "airsim_rec.txt", source / "airsim_rec.txt");
  std::ifstream in(source / "airsim_rec.txt");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const std::string name = Split(line, '\t').back();
    cv::imwrite((source / "images" / name).string(),
                cv::Mat(144, 256, CV_8UC3, cv::Scalar(90, 100, 110)));
  }
  return source;
}

TEST(AirSimPx4Recording, SceneImagesOnlyImportWithTheRecordedPoses) {
  TempDir dir;
  const fs::path source = CopyPx4Recording(dir.path());
  const fs::path settings = fs::path(SourceDir()) / "tests/import/data/airsim_px4/settings.json";
  const fs::path out = dir / "px4";
  const CommandResult imported = RunLsds("import airsim " + source.string() + " -o " +
                                         out.string() + " --settings " + settings.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  // The warning names what the recording lacks.
  EXPECT_NE(imported.output.find("warning: the source has no depth, instanceid, classid pass"),
            std::string::npos)
      << imported.output;
  const CommandResult validate = RunLsds("validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;

  const CollectionReader reader(out);
  ASSERT_EQ(reader.header().layers.size(), 1u);
  EXPECT_EQ(reader.header().layers[0].semantic, "rgb");
  EXPECT_EQ(reader.header().provenance.import["source_conventions"]["camera"], "");
  const std::vector<RecordedRow> rows =
      ReadRows(fs::path(SourceDir()) / "tests/import/data/airsim_px4/airsim_rec.txt");
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), rows.size());
  ASSERT_EQ(frames.size(), 6u);
  double centre_error = 0, axis_error = 0, time_error = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const Frame& frame = frames[k];
    const PinholeCamera& camera = frame.camera.intrinsics;
    EXPECT_EQ(camera.width, 256);
    EXPECT_EQ(camera.height, 144);
    EXPECT_NEAR(camera.fx, 221.7025033688163, 1e-9);  // CameraDefaults' 60 degrees
    EXPECT_NEAR(camera.fy, camera.fx, 1e-12);
    EXPECT_DOUBLE_EQ(camera.cx, 128);
    EXPECT_DOUBLE_EQ(camera.cy, 72);
    // Camera "" is front_center at the body origin: its centre is the
    // vehicle's, NED (x, y, z) -> ENU (y, x, -z), and it looks along the
    // body's forward axis.
    const RecordedRow& row = rows[k];
    const Eigen::Vector3d centre_enu(row.ned.y(), row.ned.x(), -row.ned.z());
    const Rigid3d cam_from_world = CamFromWorld(frame.camera);
    centre_error =
        std::max(centre_error, (CameraCenterInWorld(cam_from_world) - centre_enu).norm());
    const Eigen::Vector3d forward_ned = row.q.normalized() * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d forward_enu(forward_ned.y(), forward_ned.x(), -forward_ned.z());
    const Eigen::Vector3d optical_axis =
        cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
    axis_error = std::max(axis_error, (optical_axis - forward_enu).norm());
    time_error = std::max(time_error, std::abs(frame.time - (row.ms - rows[0].ms) / 1000));
  }
  EXPECT_LT(centre_error, 1e-12);
  EXPECT_LT(axis_error, 1e-12);
  EXPECT_LT(time_error, 1e-12);
  std::cout << "AirSim PX4: " << frames.size() << " frames, max centre error " << centre_error
            << " m, max axis error " << axis_error << ", max time error " << time_error << " s\n";
}

TEST(AirSimPx4Recording, CommandsThatNeedAMissingLayerNameItAndTheCollection) {
  TempDir dir;
  const fs::path source = CopyPx4Recording(dir.path());
  const fs::path settings = fs::path(SourceDir()) / "tests/import/data/airsim_px4/settings.json";
  const fs::path out = dir / "px4";
  ASSERT_EQ(RunLsds("import airsim " + source.string() + " -o " + out.string() + " --settings " +
                    settings.string())
                .exit_code,
            0);
  const std::string collection = (out / "collection.json").string();
  const auto expect_refused = [&](const std::string& args, const std::string& says) {
    const CommandResult run = RunLsds(args);
    EXPECT_EQ(run.exit_code, 2) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(says), std::string::npos) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(collection), std::string::npos) << args << "\n" << run.output;
  };
  expect_refused(
      "convert " + out.string() + " --to coco --images none -o " + (dir / "coco").string(),
      "no instanceid layer");
  expect_refused("backproject " + out.string() + " -o " + (dir / "cloud").string(),
                 "no flat depth layer");
  expect_refused("export-layers " + out.string() + " --layers depth -o " + (dir / "x").string(),
                 "no layer 'depth'");
  expect_refused("bundles " + out.string(), "no bundle layer");
  expect_refused("evaluate " + out.string() + " --coverage -o " + (dir / "e.json").string(),
                 "no instanceid layer");
  // What it has still converts: YOLO boxes need no layer, images the rgb one.
  const CommandResult yolo =
      RunLsds("convert " + out.string() + " --to yolo -o " + (dir / "yolo").string());
  EXPECT_EQ(yolo.exit_code, 0) << yolo.output;
}

TEST(AirSimPx4Recording, WithoutSettingsAirSimsDefaultsAreAssumedAndSaid) {
  TempDir dir;
  const fs::path source = CopyPx4Recording(dir.path());
  const fs::path out = dir / "px4";
  const CommandResult imported =
      RunLsds("import airsim " + source.string() + " -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("no settings.json"), std::string::npos) << imported.output;
  const CollectionReader reader(out);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_FALSE(frames.empty());
  EXPECT_NEAR(frames[0].camera.intrinsics.fx, 128, 1e-9);  // 90 degrees over 256 px
}

// createCameraSetting copies CameraDefaults, then a camera's CaptureSettings entries replace the
// captures of their types one by one (loadCaptureSettings) and its Gimbal replaces the gimbal
// whole (createGimbalSetting); the pawn's own cameras take CameraDefaults' captures and gimbal
// (APIPCamera::setupCameraFromSettings).
TEST(AirSimSettings, CapturesOfEachImageTypeAndTheGimbalMergeAsAirSimMergesThem) {
  const json settings = json::parse(R"({
    "CameraDefaults": {
      "CaptureSettings": [{"ImageType": 0, "Width": 640, "Height": 480, "FOV_Degrees": 70},
                          {"ImageType": 1, "Width": 320, "Height": 240}],
      "Gimbal": {"Stabilization": 1, "Pitch": -90}},
    "Vehicles": {"Drone1": {"Cameras": {
        "down": {"CaptureSettings": [{"ImageType": 5, "Width": 640, "Height": 480,
                                      "FOV_Degrees": 70}]},
        "level": {"Gimbal": {"Yaw": 30}},
        "wild": {"Gimbal": {"Stabilization": 7, "Roll": 2}}}}}})");
  const import::AirSimCamera down = Resolve(settings, "down");
  EXPECT_EQ(down.width, 640);
  EXPECT_EQ(down.height, 480);
  EXPECT_DOUBLE_EQ(down.fov_deg, 70);
  EXPECT_TRUE(down.CaptureOf(0) == (import::AirSimCapture{640, 480, 70}));
  EXPECT_TRUE(down.CaptureOf(1) == (import::AirSimCapture{320, 240, 90}));  // FOV unset: 90
  EXPECT_TRUE(down.CaptureOf(5) == (import::AirSimCapture{640, 480, 70}));
  EXPECT_TRUE(down.CaptureOf(2) == (import::AirSimCapture{256, 144, 90}));  // never listed
  EXPECT_DOUBLE_EQ(down.gimbal.stabilization, 1);
  EXPECT_DOUBLE_EQ(down.gimbal.pitch, -90);
  EXPECT_TRUE(std::isnan(down.gimbal.yaw));
  EXPECT_TRUE(std::isnan(down.gimbal.roll));
  // A camera's own Gimbal is a fresh one: Stabilization 0 unless it says.
  const import::AirSimCamera level = Resolve(settings, "level");
  EXPECT_DOUBLE_EQ(level.gimbal.stabilization, 0);
  EXPECT_DOUBLE_EQ(level.gimbal.yaw, 30);
  EXPECT_TRUE(std::isnan(level.gimbal.pitch));
  // Clipped to [0, 1] as PIPCamera does.
  EXPECT_DOUBLE_EQ(Resolve(settings, "wild").gimbal.stabilization, 1);
  // The pawn's camera "" takes CameraDefaults' gimbal.
  EXPECT_DOUBLE_EQ(Resolve(settings, "").gimbal.pitch, -90);
  EXPECT_DOUBLE_EQ(Resolve(settings, "").gimbal.stabilization, 1);
  // A gimbal without stabilization holds nothing.
  const Eigen::Matrix3d tilted = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
  EXPECT_EQ(level.gimbal.Held(tilted), tilted);
}

// The PX4 recording (a flying multirotor: its body pitches and rolls) with a gimbal on the
// recording camera: `settings` is CameraDefaults' Gimbal.
Frame FirstFrameWithGimbal(const fs::path& dir,
                           const json& gimbal,
                           std::string* output,
                           std::vector<Frame>* all = nullptr) {
  const fs::path source = CopyPx4Recording(dir);
  json settings = json::parse(
      std::ifstream(fs::path(SourceDir()) / "tests/import/data/airsim_px4/settings.json"));
  settings["CameraDefaults"]["Gimbal"] = gimbal;
  const fs::path settings_file = dir / "gimbal_settings.json";
  std::ofstream(settings_file) << settings.dump(2);
  const fs::path out = dir / "gimbal";
  const CommandResult imported = RunLsds("import airsim " + source.string() + " -o " +
                                         out.string() + " --settings " + settings_file.string());
  EXPECT_EQ(imported.exit_code, 0) << imported.output;
  *output = imported.output;
  const CommandResult validate = RunLsds("validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  std::vector<Frame> frames;
  CollectionReader(out).ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  if (all != nullptr) *all = frames;
  return frames.at(0);
}

// A stabilized gimbal holding Pitch -90 keeps the camera looking straight down whatever the body
// does; holding Pitch 0, Roll 0 and Yaw 30 it looks level at 30 degrees east of north with the
// image rows level. The camera centre stays where the mount puts it.
TEST(AirSimPx4Recording, AStabilizedGimbalHoldsTheCamerasWorldAngles) {
  TempDir dir;
  std::string output;
  std::vector<Frame> frames;
  FirstFrameWithGimbal(dir / "down", json{{"Stabilization", 1}, {"Pitch", -90}}, &output, &frames);
  const std::vector<RecordedRow> rows =
      ReadRows(fs::path(SourceDir()) / "tests/import/data/airsim_px4/airsim_rec.txt");
  ASSERT_EQ(frames.size(), rows.size());
  double body_tilt = 0, down_error = 0, centre_error = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const Rigid3d cam_from_world = CamFromWorld(frames[k].camera);
    const Eigen::Vector3d optical_axis =
        cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
    down_error = std::max(down_error, (optical_axis - Eigen::Vector3d(0, 0, -1)).norm());
    const Eigen::Vector3d up_ned = rows[k].q.normalized() * Eigen::Vector3d(0, 0, -1);
    body_tilt = std::max(body_tilt, std::acos(std::clamp(-up_ned.z(), -1.0, 1.0)));
    const Eigen::Vector3d centre_enu(rows[k].ned.y(), rows[k].ned.x(), -rows[k].ned.z());
    centre_error =
        std::max(centre_error, (CameraCenterInWorld(cam_from_world) - centre_enu).norm());
  }
  EXPECT_GT(body_tilt, 1e-4);  // the body is not level: the gimbal does the work
  EXPECT_LT(down_error, 1e-12);
  EXPECT_LT(centre_error, 1e-12);
  std::cout << "AirSim gimbal: body tilt up to " << body_tilt << " rad, optical axis off nadir "
            << down_error << "\n";

  const Frame level = FirstFrameWithGimbal(
      dir / "level", json{{"Stabilization", 1}, {"Pitch", 0}, {"Roll", 0}, {"Yaw", 30}}, &output);
  const Rigid3d cam_from_world = CamFromWorld(level.camera);
  const Eigen::Matrix3d world_from_cam = cam_from_world.rotation.inverse().toRotationMatrix();
  // NED yaw 30: north-east in ENU is (sin 30, cos 30, 0).
  EXPECT_LT((world_from_cam.col(2) - Eigen::Vector3d(0.5, std::sqrt(3) / 2, 0)).norm(), 1e-12);
  EXPECT_LT(std::abs(world_from_cam.col(0).z()), 1e-12);  // image rows level
  EXPECT_EQ(output.find("Stabilization"), std::string::npos) << output;

  // Part stabilization is read as settled, and said.
  FirstFrameWithGimbal(dir / "half", json{{"Stabilization", 0.5}, {"Pitch", -90}}, &output);
  EXPECT_NE(output.find("Gimbal has Stabilization 0.5"), std::string::npos) << output;
}

}  // namespace lsds::testing
}  // namespace lsds::testing
