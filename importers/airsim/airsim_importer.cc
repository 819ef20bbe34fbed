#include "importers/airsim/airsim_importer.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

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

constexpr double kPi = 3.14159265358979323846;
double Rad(double deg) { return deg * kPi / 180.0; }

const WorldFrame& Ned() {
  static const WorldFrame frame = WorldFrame::Make("NED", "m");
  return frame;
}

// OpenCV camera axes in the FRD camera frame: x_cv = right, y_cv = down,
// z_cv = forward.
// (the body-from-camera axes of libs/geometry/attitude.h).
Eigen::Matrix3d FrdFromOpenCv() { return BodyFromCam(); }

}  // namespace

Eigen::Matrix3d AirSimMount::BodyFromCamera() const {
  return (Eigen::AngleAxisd(Rad(yaw), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(Rad(pitch), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(Rad(roll), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Rigid3d CamFromEnuOfAirSim(const Eigen::Vector3d& vehicle_in_ned,
                           const Eigen::Quaterniond& ned_from_body,
                           const AirSimMount& mount) {
  const Eigen::Matrix3d ned_from_body_m = ned_from_body.toRotationMatrix();
  const Eigen::Matrix3d enu_from_cam =
      Ned().enu_from_frame * ned_from_body_m * mount.BodyFromCamera() * FrdFromOpenCv();
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
  const std::string depth =
      AtPointer(file, "/depth", [&] { return root.value("depth", std::string("DepthPlanar")); });
  if (depth == "DepthPlanar")
    depth_kind_ = DepthKind::kPlanar;
  else if (depth == "DepthPerspective")
    depth_kind_ = DepthKind::kPerspective;
  else
    throw Error("'depth' must be DepthPlanar or DepthPerspective", Location(file, "/depth"));
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
      target.obb.center = Ned().EnuMetresFromWorld(
          {c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>()});
      // NED and ENU are both right-handed: the box axes map as they are.
      target.obb.world_from_box = Ned().enu_from_frame * ned_from_box;
      target.obb.half_extents = {
          h.at(0).get<double>(), h.at(1).get<double>(), h.at(2).get<double>()};
      targets_.push_back(target);
    }
    return 0;
  });
}

void AirSimImporter::ReadSettings(const fs::path& path) {
  const std::string file = path.string();
  const json root = ParseJsonFile(path);
  const std::string where = "/Vehicles/" + vehicle_ + "/Cameras/" + camera_;
  AtPointer(file, where, [&] {
    const json& camera = root.at("Vehicles").at(vehicle_).at("Cameras").at(camera_);
    mount_.position_in_body = {
        camera.value("X", 0.0), camera.value("Y", 0.0), camera.value("Z", 0.0)};
    mount_.roll = camera.value("Roll", 0.0);
    mount_.pitch = camera.value("Pitch", 0.0);
    mount_.yaw = camera.value("Yaw", 0.0);
    // AirSim's defaults when CaptureSettings does not say.
    width_ = 256, height_ = 144, fov_deg_ = 90;
    const json captures = camera.value("CaptureSettings", json::array());
    for (size_t i = 0; i < captures.size(); ++i) {
      const json& capture = captures.at(i);
      const std::string at = where + "/CaptureSettings/" + std::to_string(i);
      if (IntegerAt<int64_t>(capture.value("ImageType", json(-1)), file, at + "/ImageType") != 0)
        continue;  // Scene
      width_ = IntegerAt<int>(capture.value("Width", json(width_)), file, at + "/Width", 1);
      height_ = IntegerAt<int>(capture.value("Height", json(height_)), file, at + "/Height", 1);
      fov_deg_ = capture.value("FOV_Degrees", fov_deg_);
    }
    return 0;
  });
  if (!(fov_deg_ > 0 && fov_deg_ < 180))
    throw Error("FOV_Degrees must be in (0, 180)", Location(file, where));
}

// Not yet cut at its seams (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-cognitive-complexity)
void AirSimImporter::ReadRecord(const fs::path& source) {
  rec_file_ = root_->File(source / "airsim_rec.txt");
  const std::string file = rec_file_.string();
  std::ifstream in(rec_file_);
  if (!in) throw Error("cannot open the recording", Location(file));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = Split(line, '\t');
  auto column = [&](const std::string& name, bool required) {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    if (required)
      throw Error("column '" + name + "' missing from the header", Location::Text(file, 1, 1));
    return -1;
  };
  const int vehicle = column("VehicleName", false);
  const int stamp = column("TimeStamp", true);
  const int pos[3] = {column("POS_X", true), column("POS_Y", true), column("POS_Z", true)};
  const int q[4] = {
      column("Q_W", true), column("Q_X", true), column("Q_Y", true), column("Q_Z", true)};
  const int images = column("ImageFile", true);
  const fs::path folder = source / "images";
  double first_stamp = std::numeric_limits<double>::quiet_NaN();
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> cells = Split(line, '\t');
    if (cells.size() < header.size())
      throw Error("row has " + std::to_string(cells.size()) +
                      " columns, the "
                      "header " +
                      std::to_string(header.size()),
                  Location::Text(file, number, 1));
    if (vehicle >= 0 && cells[vehicle] != vehicle_) continue;
    // The 1-based column of cell c: the row's text is the cells joined by tabs.
    auto column_of = [&](int c) {
      int at = 1;
      for (int k = 0; k < c; ++k) at += static_cast<int>(cells[k].size()) + 1;
      return at;
    };
    auto number_at = [&](int c) {
      char* end = nullptr;
      const double value = std::strtod(cells[c].c_str(), &end);
      if (end == cells[c].c_str() || *end != '\0' || !std::isfinite(value))
        throw Error(
            "column '" + header[c] + "' is '" + Excerpt(cells[c]) + "', not a finite number",
            Location::Text(file, number, column_of(c)));
      return value;
    };
    Row row;
    row.line = number;
    const double ms = number_at(stamp);  // AirSim: milliseconds
    if (std::isnan(first_stamp)) first_stamp = ms;
    row.time = (ms - first_stamp) / 1000.0;
    row.position = {number_at(pos[0]), number_at(pos[1]), number_at(pos[2])};
    row.orientation =
        Eigen::Quaterniond(number_at(q[0]), number_at(q[1]), number_at(q[2]), number_at(q[3]));
    if (std::abs(row.orientation.norm() - 1) > 1e-3)
      throw Error("quaternion (Q_W, Q_X, Q_Y, Q_Z) is not unit length",
                  Location::Text(file, number, 1));
    row.orientation.normalize();
    // img_[vehicle_]camera_type_stamp.ext; camera names may hold '_'.
    for (const std::string& name : Split(cells[images], ';')) {
      for (const auto& [type, target] : {std::pair<int, fs::path*>{0, &row.scene},
                                         {depth_kind_ == DepthKind::kPlanar ? 1 : 2, &row.depth},
                                         {5, &row.segmentation}}) {
        if (name.find("_" + camera_ + "_" + std::to_string(type) + "_") != std::string::npos)
          *target = root_->Reference(folder, name, Location::Text(file, number, column_of(images)));
      }
    }
    for (const auto& [what, path] :
         {std::pair<const char*, const fs::path*>{"Scene (type 0)", &row.scene},
          {depth_kind_ == DepthKind::kPlanar ? "DepthPlanar (type 1)" : "DepthPerspective (type 2)",
           &row.depth},
          {"Segmentation (type 5)", &row.segmentation}}) {
      if (path->empty())
        throw Error(std::string("no ") + what + " image of camera '" + camera_ + "' in ImageFile",
                    Location::Text(file, number, 1));
    }
    rows_.push_back(row);
  }
  if (rows_.empty()) throw Error("no rows of vehicle '" + vehicle_ + "'", Location(file));
}

SourceDescription AirSimImporter::Open(const fs::path& source, const ImportOptions& options) {
  if (!fs::is_directory(source))
    throw Error("an AirSim recording folder was expected", Location(source.string()));
  root_.emplace(source, options.allow_links_outside);
  // Files given by a flag are the user's choice; the defaults are the source's.
  ReadObjects(options.objects.empty() ? root_->File(source / "lsds_objects.json")
                                      : options.objects);
  ReadSettings(options.settings.empty() ? root_->File(source / "settings.json") : options.settings);
  ReadRecord(source);
  SourceDescription description;
  description.classes = classes_;
  description.frame_count = static_cast<int64_t>(rows_.size());
  description.semantics = {"rgb", "classid", "instanceid", "depth"};
  description.depth_kind = depth_kind_;
  description.truth_origin = {{"rgb", "imported"},
                              {"instanceid", "imported"},
                              {"classid", "imported"},
                              {"depth", "imported"},
                              {"camera", "imported"},
                              {"obb", "imported"}};
  description.source_conventions = {
      {"world_frame", "NED"},
      {"length_unit", "m"},
      {"pose", "vehicle body (FRD) in NED + settings.json camera mount"},
      {"depth",
       depth_kind_ == DepthKind::kPlanar ? "DepthPlanar PFM, m" : "DepthPerspective PFM, m"},
      {"pfm_rows", "top row first (AirSim), not the PFM specification's"},
      {"converted_to", "ENU m"}};
  return description;
}

SourceFrame AirSimImporter::ReadFrame(int64_t index) {
  const Row& row = rows_.at(static_cast<size_t>(index));
  SourceFrame frame;
  frame.time = row.time;
  frame.sequence = "airsim-" + vehicle_;
  frame.shot = 0;
  frame.camera.intrinsics = PinholeCamera::FromHorizontalFov(width_, height_, fov_deg_);
  const Rigid3d cam_from_world = CamFromEnuOfAirSim(row.position, row.orientation, mount_);
  SetCamFromWorld(cam_from_world, &frame.camera);

  auto read_png = [&](const fs::path& path) {
    cv::Mat image = ReadImage(path, cv::IMREAD_COLOR);
    if (image.empty()) throw Error("not a readable PNG", Location(path.string()));
    if (image.cols != width_ || image.rows != height_)
      throw Error("image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                      ", settings.json says " + std::to_string(width_) + "x" +
                      std::to_string(height_),
                  Location(path.string()));
    return image;
  };
  const cv::Mat scene = read_png(row.scene);
  exr::FlatImage& rgb = frame.flat["rgb"] = exr::FlatImage(width_, height_);
  float* channel[3] = {rgb.AddChannel("R", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("G", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("B", exr::PixelType::kHalf).floats.data()};
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) {
      const cv::Vec3b bgr = scene.at<cv::Vec3b>(j, i);
      for (int c = 0; c < 3; ++c) channel[c][rgb.Index(i, j)] = LinearFromSrgb8(bgr[2 - c]);
    }

  const PfmImage pfm = ReadPfm(row.depth, PfmRows::kTopFirst);
  if (pfm.width != width_ || pfm.height != height_ || pfm.channels != 1)
    throw Error(
        "depth PFM is not " + std::to_string(width_) + "x" + std::to_string(height_) + " greyscale",
        Location(row.depth.string()));
  exr::FlatImage& depth = frame.flat["depth"] = exr::FlatImage(width_, height_);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  z = pfm.values;
  for (size_t p = 0; p < z.size(); ++p) {
    float& value = z[p];
    if (std::isnan(value) || value < 0)
      throw Error(std::isnan(value) ? "NaN depth" : "negative depth",
                  Location::Pixel(row.depth.string(),
                                  index,
                                  static_cast<int>(p % width_),
                                  static_cast<int>(p / width_)));
    if (value >= sky_depth_m_) value = std::numeric_limits<float>::infinity();
  }

  const cv::Mat segmentation = read_png(row.segmentation);
  exr::FlatImage& instances = frame.flat["instanceid"] = exr::FlatImage(width_, height_);
  exr::FlatImage& classes = frame.flat["classid"] = exr::FlatImage(width_, height_);
  std::vector<uint32_t>& instance = instances.AddChannel("id", exr::PixelType::kUint).uints;
  std::vector<uint32_t>& klass = classes.AddChannel("id", exr::PixelType::kUint).uints;
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) {
      const cv::Vec3b bgr = segmentation.at<cv::Vec3b>(j, i);
      const auto found = by_colour_.find({bgr[2], bgr[1], bgr[0]});
      if (found == by_colour_.end()) continue;  // not listed: background
      instance[instances.Index(i, j)] = found->second.instance_id;
      klass[classes.Index(i, j)] = found->second.class_id;
    }
  frame.targets = targets_;
  return frame;
}

}  // namespace lsds::import
