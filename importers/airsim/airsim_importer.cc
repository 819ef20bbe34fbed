#include "importers/airsim/airsim_importer.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "importers/pfm.h"
#include "importers/source_json.h"
#include "importers/source_png.h"
#include "libs/geometry/world_frame.h"
#include "libs/imaging/image_codecs.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/srgb.h"
#include "libs/util/strings.h"
#include "libs/util/text_check.h"

namespace lsds::import {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const WorldFrame& Ned() {
  static const WorldFrame frame = WorldFrame::Make("NED", "m");
  return frame;
}

// OpenCV camera axes in the FRD camera frame: x_cv = right, y_cv = down,
// z_cv = forward.
// (the body-from-camera axes of libs/geometry/attitude.h).
Eigen::Matrix3d FrdFromOpenCv() { return BodyFromCam(); }

// Which depth type the sidecar asks for when the recording holds both; none:
// the one recorded (DepthPlanar first).
std::optional<DepthKind> AskedDepthType(const json& sidecar, const std::string& file) {
  if (!sidecar.contains("depth")) return std::nullopt;
  const std::string depth = StringAt(sidecar.at("depth"), file, "/depth");
  if (depth == "DepthPlanar") return DepthKind::kPlanar;
  if (depth == "DepthPerspective") return DepthKind::kPerspective;
  throw Error("'depth' must be DepthPlanar or DepthPerspective", Location(file, "/depth"));
}

const char* ImageTypeName(int image_type) {
  switch (image_type) {
    case 1:
      return "DepthPlanar (type 1)";
    case 2:
      return "DepthPerspective (type 2)";
    case 5:
      return "Segmentation (type 5)";
    default:
      return "Scene (type 0)";
  }
}

}  // namespace

Rigid3d CamFromEnuOfAirSim(const Eigen::Vector3d& vehicle_in_ned,
                           const Eigen::Quaterniond& ned_from_body,
                           const AirSimMount& mount,
                           const AirSimGimbal& gimbal) {
  const Eigen::Matrix3d ned_from_body_m = ned_from_body.toRotationMatrix();
  const Eigen::Matrix3d enu_from_cam = Ned().enu_from_frame *
                                       gimbal.Held(ned_from_body_m * mount.BodyFromCamera()) *
                                       FrdFromOpenCv();
  const Eigen::Vector3d centre =
      Ned().EnuMetresFromWorld(vehicle_in_ned + ned_from_body_m * mount.position_in_body);
  const Eigen::Quaterniond cam_from_enu(Eigen::Matrix3d(enu_from_cam.transpose()));
  return Rigid3d(cam_from_enu.normalized(), -(cam_from_enu.normalized() * centre));
}

void AirSimVehicleOfCamFromEnu(const Rigid3d& cam_from_enu,
                               const AirSimMount& mount,
                               Eigen::Vector3d* vehicle_in_ned,
                               Eigen::Quaterniond* ned_from_body) {
  const Eigen::Matrix3d enu_from_cam = cam_from_enu.rotation.toRotationMatrix().transpose();
  const Eigen::Matrix3d ned_from_body_m = Ned().enu_from_frame.transpose() * enu_from_cam *
                                          FrdFromOpenCv().transpose() *
                                          mount.BodyFromCamera().transpose();
  *ned_from_body = Eigen::Quaterniond(ned_from_body_m).normalized();
  *vehicle_in_ned = Ned().WorldFromEnuMetres(CameraCenterInWorld(cam_from_enu)) -
                    ned_from_body_m * mount.position_in_body;
}

void AirSimImporter::ReadObjects(const fs::path& path) {
  const std::string file = path.string();
  const json root = ParseJsonFile(path);
  AtPointer(file, "/format", [&] {
    if (root.at("format").get<std::string>() != "lsds-airsim-objects")
      throw Error("'format' must be \"lsds-airsim-objects\"", Location(file, "/format"));
    return 0;
  });
  vehicle_ =
      AtPointer(file, "/vehicle", [&] { return root.value("vehicle", std::string("Drone1")); });
  camera_ = AtPointer(file, "/camera", [&] { return root.value("camera", std::string("0")); });
  asked_depth_ = AskedDepthType(root, file);
  sky_depth_m_ = AtPointer(file, "/sky_depth_m", [&] { return root.value("sky_depth_m", 1e4); });
  std::set<uint32_t> class_ids, instance_ids;
  AtPointer(file, "/classes", [&] {
    for (size_t i = 0; i < root.at("classes").size(); ++i) {
      const json& c = root.at("classes").at(i);
      const std::string where = "/classes/" + std::to_string(i);
      const ClassInfo info{IdAt(c.at("id"), file, where + "/id"),
                           StringAt(c.at("name"), file, where + "/name")};
      if (info.id == 0 || !class_ids.insert(info.id).second)
        throw Error("class ids must be > 0 and unique",
                    Location(file, "/classes/" + std::to_string(i) + "/id"));
      classes_.push_back(info);
    }
    return 0;
  });
  AtPointer(file, "/objects", [&] {
    for (size_t i = 0; i < root.at("objects").size(); ++i) {
      const json& o = root.at("objects").at(i);
      const std::string where = "/objects/" + std::to_string(i);
      const json& rgb = o.at("color");
      std::array<uint8_t, 3> colour{};
      for (int ch = 0; ch < 3; ++ch)
        colour[ch] = IntegerAt<uint8_t>(rgb.at(ch), file, where + "/color/" + std::to_string(ch));
      const Labelled label{IdAt(o.at("instance_id"), file, where + "/instance_id"),
                           IdAt(o.at("class_id"), file, where + "/class_id")};
      if (label.instance_id == 0 || !instance_ids.insert(label.instance_id).second)
        throw Error("instance ids must be > 0 and unique", Location(file, where + "/instance_id"));
      if (!class_ids.count(label.class_id))
        throw Error("class_id " + std::to_string(label.class_id) + " is not in 'classes'",
                    Location(file, where + "/class_id"));
      // AirSim's palette has 256 colours for ids hashed from names: two
      // objects on one colour cannot be told apart.
      if (!by_colour_.emplace(colour, label).second)
        throw Error(
            "two objects share the segmentation colour; give them "
            "distinct ids with simSetSegmentationObjectID",
            Location(file, where + "/color"));
      if (!o.contains("obb")) continue;
      ObjectIdentity target;
      target.instance_id = label.instance_id;
      target.class_id = label.class_id;
      target.name = o.value("name", "object#" + std::to_string(i));
      target.asset = o.value("asset", "");
      const json& obb = o.at("obb");
      Eigen::Matrix3d ned_from_box;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          ned_from_box(r, c) = obb.at("rotation").at(r).at(c).get<double>();
      if ((ned_from_box.transpose() * ned_from_box - Eigen::Matrix3d::Identity())
                  .cwiseAbs()
                  .maxCoeff() > 1e-6 ||
          ned_from_box.determinant() < 0)
        throw Error("rotation must be a proper rotation matrix",
                    Location(file, where + "/obb/rotation"));
      const json& c = obb.at("center");
      const json& h = obb.at("half_extents");
      OrientedBox& box = target.obb.emplace();
      box.center = Ned().EnuMetresFromWorld(
          {c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>()});
      // NED and ENU are both right-handed: the box axes map as they are.
      box.world_from_box = Ned().enu_from_frame * ned_from_box;
      box.half_extents = {h.at(0).get<double>(), h.at(1).get<double>(), h.at(2).get<double>()};
      targets_.push_back(target);
    }
    return 0;
  });
}

bool AirSimImporter::SharesSceneCapture(int image_type) {
  const AirSimCapture scene = camera_settings_.CaptureOf(0);
  const AirSimCapture own = camera_settings_.CaptureOf(image_type);
  if (own == scene) return true;
  auto text = [](const AirSimCapture& c) {
    return std::to_string(c.width) + "x" + std::to_string(c.height) + " at " +
           FormatNumber(c.fov_deg) + " degrees";
  };
  warnings_.push_back("the " + std::string(ImageTypeName(image_type)) +
                      " images are not read: settings.json gives them a capture of their own (" +
                      text(own) + ", the Scene's " + text(scene) +
                      "), whose pixels are not the Scene image's");
  return false;
}

void AirSimImporter::ReadSettings(const fs::path& path) {
  // No settings.json: AirSim's own defaults (what an empty settings file gives).
  const json root = path.empty() ? json::object() : ParseJsonFile(path);
  if (path.empty())
    warnings_.push_back(
        "no settings.json (give --settings): AirSim's defaults assumed, a 256x144 Scene "
        "capture with a 90 degree FOV and the pawn's own camera mount");
  camera_settings_ = ResolveAirSimCamera(
      root, path.empty() ? std::string("settings.json") : path.string(), vehicle_, camera_);
  if (path.empty()) camera_settings_.capture_origin = "AirSim's defaults (no settings.json)";
  const double s = camera_settings_.gimbal.stabilization;
  if (s > 0 && s < 1)
    warnings_.push_back(
        "the camera's Gimbal has Stabilization " + FormatNumber(s) +
        ": AirSim moves the held angles there tick by tick (held * s + current * (1 - s)), "
        "reaching them when the vehicle is at rest; the camera poses are the held ones (the lag "
        "while the vehicle turns is not recorded)");
}

namespace {

// One image name of an ImageFile cell, `img_[<vehicle>_]<camera>_<type>_<t>.<ext>`
// (RecordingFile.cpp): the camera (may be "" or hold '_') and the image type.
struct ImageName {
  std::string camera;
  int type = -1;
};
std::optional<ImageName> ParseImageName(const std::string& name, const std::string& vehicle) {
  // The file's name: a folder before it is the confinement rule's to judge.
  const std::string base = name.substr(name.find_last_of("/\\") + 1);
  if (base.rfind("img_", 0) != 0) return std::nullopt;
  std::string rest = base.substr(4);
  const size_t dot = rest.rfind('.');
  if (dot != std::string::npos) rest.resize(dot);
  auto pop_number = [&]() -> std::optional<int64_t> {
    const size_t cut = rest.rfind('_');
    if (cut == std::string::npos) return std::nullopt;
    const std::optional<int64_t> value =
        ParseInteger(rest.substr(cut + 1), 0, std::numeric_limits<int64_t>::max());
    rest.resize(cut);
    return value;
  };
  if (!pop_number()) return std::nullopt;  // the time stamp
  const std::optional<int64_t> type = pop_number();
  if (!type || *type > 100) return std::nullopt;
  // Newer AirSim puts the vehicle's name first.
  if (!vehicle.empty() && rest.rfind(vehicle + "_", 0) == 0) rest = rest.substr(vehicle.size() + 1);
  return ImageName{rest, static_cast<int>(*type)};
}

// airsim_rec.txt: the header's columns and the data rows (line numbers kept
// for messages).
struct RecordText {
  std::vector<std::string> header;
  std::vector<std::pair<int, std::vector<std::string>>> rows;
  int Column(const std::string& name, bool required, const std::string& file) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    if (required)
      throw Error("column '" + name + "' missing from the header", Location::Text(file, 1, 1));
    return -1;
  }
};

RecordText ReadRecordText(const fs::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw Error("cannot open the recording", Location(file));
  RecordText text;
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  text.header = Split(line, '\t');
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> cells = Split(line, '\t');
    if (cells.size() < text.header.size())
      throw Error("row has " + std::to_string(cells.size()) + " columns, the header " +
                      std::to_string(text.header.size()),
                  Location::Text(file, number, 1));
    text.rows.emplace_back(number, std::move(cells));
  }
  return text;
}

}  // namespace

void AirSimImporter::ChooseVehicleAndCamera(const fs::path& rec_file) {
  const std::string file = rec_file.string();
  const RecordText text = ReadRecordText(rec_file);
  const int vehicle = text.Column("VehicleName", false, file);
  const int images = text.Column("ImageFile", true, file);
  std::set<std::string> vehicles, cameras;
  for (const auto& [number, cells] : text.rows) vehicles.insert(vehicle >= 0 ? cells[vehicle] : "");
  if (vehicles.size() > 1)
    throw Error("the recording holds several vehicles (" +
                    Join(std::vector<std::string>(vehicles.begin(), vehicles.end()), ", ") +
                    "): name one in lsds_objects.json 'vehicle'",
                Location(file));
  vehicle_ = vehicles.empty() ? vehicle_ : *vehicles.begin();
  for (const auto& [number, cells] : text.rows)
    for (const std::string& name : Split(cells[images], ';'))
      if (const auto image = ParseImageName(name, vehicle_); image && image->type == 0)
        cameras.insert(image->camera);
  if (cameras.size() > 1)
    throw Error(
        "the recording holds Scene images of several cameras: name one in "
        "lsds_objects.json 'camera'",
        Location(file));
  if (!cameras.empty()) camera_ = *cameras.begin();
}

namespace {

// The columns ReadRecord reads, by index into a row's cells (-1: no VehicleName).
struct RecordColumns {
  int vehicle = -1, stamp = -1;
  int pos[3] = {-1, -1, -1};
  int q[4] = {-1, -1, -1, -1};
  int images = -1;
};

RecordColumns FindColumns(const RecordText& text, const std::string& file) {
  RecordColumns columns;
  columns.vehicle = text.Column("VehicleName", false, file);
  columns.stamp = text.Column("TimeStamp", true, file);
  columns.pos[0] = text.Column("POS_X", true, file);
  columns.pos[1] = text.Column("POS_Y", true, file);
  columns.pos[2] = text.Column("POS_Z", true, file);
  columns.q[0] = text.Column("Q_W", true, file);
  columns.q[1] = text.Column("Q_X", true, file);
  columns.q[2] = text.Column("Q_Y", true, file);
  columns.q[3] = text.Column("Q_Z", true, file);
  columns.images = text.Column("ImageFile", true, file);
  return columns;
}

// One data row's cells, with the place of each in the file for messages.
struct RecordCells {
  const std::vector<std::string>& header;
  const std::vector<std::string>& cells;
  const std::string& file;
  int number;  // the line

  // The 1-based column of cell c: the row's text is the cells joined by tabs.
  int ColumnOf(int c) const {
    int at = 1;
    for (int k = 0; k < c; ++k) at += static_cast<int>(cells[k].size()) + 1;
    return at;
  }

  double NumberAt(int c) const {
    char* end = nullptr;
    const double value = std::strtod(cells[c].c_str(), &end);
    if (end == cells[c].c_str() || *end != '\0' || !std::isfinite(value))
      throw Error("column '" + header[c] + "' is '" + Excerpt(cells[c]) + "', not a finite number",
                  Location::Text(file, number, ColumnOf(c)));
    return value;
  }
};

// A row's time stamp (AirSim: milliseconds), position and unit orientation.
struct RecordPose {
  double ms = 0;
  Eigen::Vector3d position;
  Eigen::Quaterniond orientation;
};

RecordPose ReadPose(const RecordCells& row, const RecordColumns& columns) {
  RecordPose pose;
  pose.ms = row.NumberAt(columns.stamp);
  pose.position = {
      row.NumberAt(columns.pos[0]), row.NumberAt(columns.pos[1]), row.NumberAt(columns.pos[2])};
  pose.orientation = Eigen::Quaterniond(row.NumberAt(columns.q[0]),
                                        row.NumberAt(columns.q[1]),
                                        row.NumberAt(columns.q[2]),
                                        row.NumberAt(columns.q[3]));
  if (std::abs(pose.orientation.norm() - 1) > 1e-3)
    throw Error("quaternion (Q_W, Q_X, Q_Y, Q_Z) is not unit length",
                Location::Text(row.file, row.number, 1));
  pose.orientation.normalize();
  return pose;
}

}  // namespace

// The camera's images of a row, by type.
std::map<int, fs::path> AirSimImporter::ImagesOfRow(const std::string& image_file_cell,
                                                    const fs::path& folder,
                                                    const Location& where) const {
  std::map<int, fs::path> by_type;
  for (const std::string& name : Split(image_file_cell, ';')) {
    // Every name in the data must be a relative path inside the source, read
    // or not (the lexical rule of libs/util/confined_path.h; Reference throws
    // its message).
    if (!ReferenceProblem(name, "the source").empty()) root_->Reference(folder, name, where);
    const std::optional<ImageName> image = ParseImageName(name, vehicle_);
    if (image && image->camera == camera_)
      by_type[image->type] = root_->Reference(folder, name, where);
  }
  return by_type;
}

// The passes of the first row are those of the recording.
void AirSimImporter::ChoosePasses(const std::map<int, fs::path>& by_type) {
  if (!asked_depth_)
    asked_depth_ =
        by_type.count(1) || !by_type.count(2) ? DepthKind::kPlanar : DepthKind::kPerspective;
  depth_kind_ = *asked_depth_;
  has_depth_ = by_type.count(depth_kind_ == DepthKind::kPlanar ? 1 : 2) != 0;
  has_segmentation_ = by_type.count(5) != 0 && has_sidecar_;
  if (by_type.count(5) && !has_sidecar_)
    warnings_.push_back(
        "the Segmentation (type 5) images are not read: without lsds_objects.json their "
        "colours name no object");
  // A capture of its own size or FOV is another camera than the Scene's, whose pixels are
  // not the frame's: not read.
  has_depth_ = has_depth_ && SharesSceneCapture(depth_kind_ == DepthKind::kPlanar ? 1 : 2);
  has_segmentation_ = has_segmentation_ && SharesSceneCapture(5);
}

// Every row holds the passes of the recording.
void AirSimImporter::AssignImages(const std::map<int, fs::path>& by_type,
                                  const Location& where,
                                  Row* row) const {
  const char* depth_name =
      depth_kind_ == DepthKind::kPlanar ? "DepthPlanar (type 1)" : "DepthPerspective (type 2)";
  for (const auto& [type, what, wanted, target] :
       {std::tuple<int, const char*, bool, fs::path*>{0, "Scene (type 0)", true, &row->scene},
        {depth_kind_ == DepthKind::kPlanar ? 1 : 2, depth_name, has_depth_, &row->depth},
        {5, "Segmentation (type 5)", has_segmentation_, &row->segmentation}}) {
    if (!wanted) continue;
    const auto found = by_type.find(type);
    if (found == by_type.end())
      throw Error(std::string("no ") + what + " image of camera '" + camera_ + "' in ImageFile" +
                      (rows_.empty() ? "" : " (the first row has one)"),
                  where);
    *target = found->second;
  }
}

void AirSimImporter::ReadRecord(const fs::path& source) {
  const std::string file = rec_file_.string();
  const RecordText text = ReadRecordText(rec_file_);
  const RecordColumns columns = FindColumns(text, file);
  const fs::path folder = source / "images";
  double first_stamp = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [number, cells] : text.rows) {
    if (columns.vehicle >= 0 && cells[columns.vehicle] != vehicle_) continue;
    const RecordCells row_cells{text.header, cells, file, number};
    const RecordPose pose = ReadPose(row_cells, columns);
    if (std::isnan(first_stamp)) first_stamp = pose.ms;
    Row row;
    row.line = number;
    row.time = (pose.ms - first_stamp) / 1000.0;
    row.position = pose.position;
    row.orientation = pose.orientation;
    const std::map<int, fs::path> by_type =
        ImagesOfRow(cells[columns.images],
                    folder,
                    Location::Text(file, number, row_cells.ColumnOf(columns.images)));
    if (rows_.empty()) ChoosePasses(by_type);
    AssignImages(by_type, Location::Text(file, number, 1), &row);
    rows_.push_back(row);
  }
  if (rows_.empty()) throw Error("no rows of vehicle '" + vehicle_ + "'", Location(file));
}

SourceDescription AirSimImporter::Open(const fs::path& source, const ImportOptions& options) {
  if (!fs::is_directory(source))
    throw Error("an AirSim recording folder was expected", Location(source.string()));
  root_.emplace(source, options.allow_links_outside);
  rec_file_ = root_->File(source / "airsim_rec.txt");
  // Files given by a flag are the user's choice; the defaults are the source's.
  // Without a sidecar the recording says which vehicle and camera, and no
  // pixel names an object.
  const fs::path objects =
      options.objects.empty() ? root_->File(source / "lsds_objects.json") : options.objects;
  has_sidecar_ = !options.objects.empty() || fs::exists(objects);
  if (has_sidecar_)
    ReadObjects(objects);
  else
    ChooseVehicleAndCamera(rec_file_);
  const fs::path settings =
      options.settings.empty() ? root_->File(source / "settings.json") : options.settings;
  ReadSettings(options.settings.empty() && !fs::exists(settings) ? fs::path() : settings);
  ReadRecord(source);
  SourceDescription description;
  description.classes = classes_;
  description.frame_count = static_cast<int64_t>(rows_.size());
  description.semantics = {"rgb"};
  description.truth_origin = {{"rgb", "imported"}, {"camera", "imported"}};
  if (has_segmentation_) {
    description.semantics.insert(description.semantics.end(), {"classid", "instanceid"});
    description.truth_origin.insert(
        {{"instanceid", "imported"}, {"classid", "imported"}, {"obb", "imported"}});
  }
  if (has_depth_) {
    description.semantics.push_back("depth");
    description.truth_origin["depth"] = "imported";
  }
  description.depth_kind = depth_kind_;
  description.warnings = warnings_;
  description.source_conventions = {
      {"world_frame", "NED"},
      {"length_unit", "m"},
      {"vehicle", vehicle_},
      {"camera", camera_},
      {"pose",
       "vehicle body (FRD) in NED + camera mount (" + camera_settings_.mount_origin + ")" +
           (camera_settings_.gimbal.stabilization > 0 ? " + the Gimbal's held angles" : "")},
      {"capture", camera_settings_.capture_origin},
      {"converted_to", "ENU m"}};
  if (has_depth_) {
    description.source_conventions["depth"] =
        depth_kind_ == DepthKind::kPlanar ? "DepthPlanar PFM, m" : "DepthPerspective PFM, m";
    description.source_conventions["pfm_rows"] =
        "top row first (AirSim), not the PFM specification's";
  }
  return description;
}

SourceFrame AirSimImporter::ReadFrame(int64_t index) {
  const Row& row = rows_.at(static_cast<size_t>(index));
  SourceFrame frame;
  frame.time = row.time;
  frame.sequence = "airsim-" + vehicle_;
  frame.shot = 0;
  const int width = camera_settings_.width, height = camera_settings_.height;
  frame.camera.intrinsics =
      PinholeCamera::FromHorizontalFov(width, height, camera_settings_.fov_deg);
  const Rigid3d cam_from_world = CamFromEnuOfAirSim(
      row.position, row.orientation, camera_settings_.mount, camera_settings_.gimbal);
  SetCamFromWorld(cam_from_world, &frame.camera);

  const cv::Mat scene = ReadScenePng(row.scene);
  exr::FlatImage& rgb = frame.flat["rgb"] = exr::FlatImage(width, height);
  float* channel[3] = {rgb.AddChannel("R", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("G", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("B", exr::PixelType::kHalf).floats.data()};
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const cv::Vec3b bgr = scene.at<cv::Vec3b>(j, i);
      for (int c = 0; c < 3; ++c) channel[c][rgb.Index(i, j)] = LinearFromSrgb8(bgr[2 - c]);
    }

  if (has_segmentation_) frame.targets = targets_;
  if (has_depth_) ReadDepth(row.depth, index, &frame);
  if (has_segmentation_) ReadSegmentation(row.segmentation, &frame);
  return frame;
}

void AirSimImporter::ReadDepth(const fs::path& path, int64_t index, SourceFrame* frame) const {
  const int width = camera_settings_.width, height = camera_settings_.height;
  const PfmImage pfm = ReadPfm(path, PfmRows::kTopFirst);
  if (pfm.width != width || pfm.height != height || pfm.channels != 1)
    throw Error(
        "depth PFM is not " + std::to_string(width) + "x" + std::to_string(height) + " greyscale",
        Location(path.string()));
  exr::FlatImage& depth = frame->flat["depth"] = exr::FlatImage(width, height);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  z = pfm.values;
  for (size_t p = 0; p < z.size(); ++p) {
    float& value = z[p];
    if (std::isnan(value) || value < 0)
      throw Error(
          std::isnan(value) ? "NaN depth" : "negative depth",
          Location::Pixel(
              path.string(), index, static_cast<int>(p % width), static_cast<int>(p / width)));
    if (value >= sky_depth_m_) value = std::numeric_limits<float>::infinity();
  }
}

void AirSimImporter::ReadSegmentation(const fs::path& path, SourceFrame* frame) const {
  const int width = camera_settings_.width, height = camera_settings_.height;
  const cv::Mat segmentation = ReadScenePng(path);
  exr::FlatImage& instances = frame->flat["instanceid"] = exr::FlatImage(width, height);
  exr::FlatImage& classes = frame->flat["classid"] = exr::FlatImage(width, height);
  std::vector<uint32_t>& instance = instances.AddChannel("id", exr::PixelType::kUint).uints;
  std::vector<uint32_t>& klass = classes.AddChannel("id", exr::PixelType::kUint).uints;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const cv::Vec3b bgr = segmentation.at<cv::Vec3b>(j, i);
      const auto found = by_colour_.find({bgr[2], bgr[1], bgr[0]});
      if (found == by_colour_.end()) continue;  // not listed: background
      instance[instances.Index(i, j)] = found->second.instance_id;
      klass[classes.Index(i, j)] = found->second.class_id;
    }
}

cv::Mat AirSimImporter::ReadScenePng(const fs::path& path) const {
  const int width = camera_settings_.width, height = camera_settings_.height;
  cv::Mat image = ReadImage(path, cv::IMREAD_COLOR);
  if (image.empty()) throw Error("not a readable PNG", Location(path.string()));
  if (image.cols != width || image.rows != height)
    throw Error("image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                    ", settings.json says " + std::to_string(width) + "x" + std::to_string(height) +
                    " (" + camera_settings_.capture_origin + ")",
                Location(path.string()));
  return image;
}

}  // namespace lsds::import
