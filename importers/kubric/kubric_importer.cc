#include "importers/kubric/kubric_importer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "importers/indexed_png.h"
#include "importers/source_json.h"
#include "importers/source_png.h"
#include "libs/imaging/image_codecs.h"
#include "libs/util/error.h"

namespace lsds::import {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string FrameFile(const char* stem, int64_t frame, const char* ext) {
  char text[64];
  std::snprintf(text, sizeof text, "%s_%05lld.%s", stem, static_cast<long long>(frame), ext);
  return text;
}

// The class of a Kubric instance: MOVi-C..F store a `category`, MOVi-A/B a
// `shape`; otherwise the asset.
std::string ClassName(const json& instance) {
  for (const char* key : {"category", "shape", "asset_id"}) {
    const auto it = instance.find(key);
    if (it == instance.end()) continue;
    if (it->is_string()) return it->get<std::string>();
    if (it->is_number_integer()) return std::string(key) + "_" + std::to_string(it->get<int64_t>());
  }
  return "object";
}

// Blender renders background pixels at its far value (1e10 before the
// z-to-ray scaling); anything this far is no surface.
constexpr float kBackgroundDepth = 1e9f;

// The OBB of Kubric's 8 corners, itertools.product(x, y, z bounds) order:
// corner 4*ix + 2*iy + iz, each rotated by the object's quaternion and moved
// to its position (core/objects.py bbox_3d).
OrientedBox ObbFromCorners(const json& corners, const std::string& file, const std::string& where) {
  Eigen::Vector3d c[8];
  AtPointer(file, where, [&] {
    if (!corners.is_array() || corners.size() != 8)
      throw json::type_error::create(302, "expected 8 corners", &corners);
    for (int k = 0; k < 8; ++k) c[k] = JsonNumbers<3>(corners.at(k));
    return 0;
  });
  OrientedBox box;
  box.center = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : c) box.center += p / 8.0;
  const Eigen::Vector3d edge[3] = {c[4] - c[0], c[2] - c[0], c[1] - c[0]};
  for (int a = 0; a < 3; ++a) {
    const double length = edge[a].norm();
    if (!(length > 0)) throw Error("degenerate box (zero edge)", Location(file, where));
    box.half_extents[a] = 0.5 * length;
    box.world_from_box.col(a) = edge[a] / length;
  }
  const Eigen::Matrix3d& r = box.world_from_box;
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
      r.determinant() < 0)
    throw Error("the 8 corners are not a box in product(x, y, z) order", Location(file, where));
  return box;
}

}  // namespace

SourceDescription KubricImporter::Open(const fs::path& source, const ImportOptions& options) {
  scene_ = source;
  root_.emplace(source, options.allow_links_outside);
  metadata_file_ = root_->File(source / "metadata.json").string();
  if (!fs::is_regular_file(metadata_file_))
    throw Error("not a Kubric scene folder: no metadata.json", Location(source.string()));
  const json metadata = ParseJsonFile(metadata_file_);
  int64_t frames = 0;
  AtPointer(metadata_file_, "/metadata", [&] {
    const json& m = metadata.at("metadata");
    const json& resolution = m.at("resolution");
    width_ = IntegerAt<int>(resolution.at(0), metadata_file_, "/metadata/resolution/0");
    height_ = IntegerAt<int>(resolution.at(1), metadata_file_, "/metadata/resolution/1");
    frames = IntegerAt<int64_t>(m.at("num_frames"), metadata_file_, "/metadata/num_frames");
    frame_rate_ = m.value("frame_rate", 1.0);
    return 0;
  });
  if (width_ < 1 || height_ < 1 || frames < 1 || !(frame_rate_ > 0))
    throw Error("resolution, num_frames and frame_rate must be positive",
                Location(metadata_file_, "/metadata"));
  camera_ = AtPointer(metadata_file_, "/camera", [&] { return metadata.at("camera"); });
  const Eigen::Matrix<double, 9, 1> k =
      AtPointer(metadata_file_, "/camera/K", [&] { return JsonNumbers<9>(camera_.at("K")); });
  for (int r = 0; r < 9; ++r) normalised_k_(r / 3, r % 3) = k[r];
  for (const char* key : {"positions", "quaternions"}) {
    const std::string where = std::string("/camera/") + key;
    AtPointer(metadata_file_, where, [&] {
      if (camera_.at(key).size() != static_cast<size_t>(frames))
        throw json::type_error::create(
            302, "expected one entry per frame (num_frames)", &camera_.at(key));
      return 0;
    });
  }
  instances_ = AtPointer(metadata_file_, "/instances", [&] { return metadata.at("instances"); });
  if (!instances_.is_array())
    throw Error("expected an array of instances", Location(metadata_file_, "/instances"));
  // The segmentation PNG is 8-bit: kb.write_palette_png casts the index to
  // uint8, so instance 256 would read as 0.
  if (instances_.size() > 255)
    throw Error(
        "more than 255 instances: Kubric's 8-bit segmentation wraps "
        "and cannot tell them apart",
        Location(metadata_file_, "/instances"));
  std::set<std::string> names;
  for (const json& instance : instances_) names.insert(ClassName(instance));
  SourceDescription description;
  uint32_t next = 1;
  std::map<std::string, uint32_t> class_ids;
  for (const std::string& n : names) {
    class_ids[n] = next;
    description.classes.push_back({next++, n});
  }
  for (size_t i = 0; i < instances_.size(); ++i) {
    const json& instance = instances_[i];
    const std::string where = "/instances/" + std::to_string(i) + "/bboxes_3d";
    AtPointer(metadata_file_, where, [&] {
      if (instance.at("bboxes_3d").size() != static_cast<size_t>(frames))
        throw json::type_error::create(
            302, "expected one box per frame", &instance.at("bboxes_3d"));
      return 0;
    });
    Instance identity;
    identity.class_id = class_ids.at(ClassName(instance));
    const auto asset = instance.find("asset_id");
    if (asset != instance.end() && asset->is_string()) identity.asset = asset->get<std::string>();
    identity.name = ClassName(instance) + "#" + std::to_string(i);
    identities_.push_back(identity);
  }
  description.frame_count = frames;
  description.semantics = {"rgb", "classid", "instanceid", "depth"};
  description.depth_kind = DepthKind::kPerspective;
  description.truth_origin = {{"rgb", "imported"},
                              {"instanceid", "imported"},
                              {"classid", "imported"},
                              {"depth", "imported"},
                              {"camera", "imported"},
                              {"obb", "imported"}};
  description.source_conventions = {
      {"world_frame", "Blender world (z up), declared ENU"},
      {"length_unit", "m"},
      {"camera_frame", "Blender camera: looks down -Z, +Y up (WXYZ quaternions)"},
      {"intrinsics", "K normalised by the image size, negated 2nd and 3rd rows"},
      {"depth", "float32 TIFF, distance along the ray (z_to_depth)"},
      {"converted_to", "ENU m, OpenCV camera, pixel-edge intrinsics"}};
  return description;
}

SourceFrame KubricImporter::ReadFrame(int64_t index) {
  const std::string at = "/" + std::to_string(index);
  SourceFrame frame;
  frame.time = static_cast<double>(index) / frame_rate_;
  frame.sequence = scene_.filename().string();
  frame.shot = 0;  // one continuous camera path per scene
  PinholeCamera& camera = frame.camera.intrinsics;
  camera.width = width_, camera.height = height_;
  // PerspectiveCamera.intrinsics: [[fx, 0, -px], [0, -fy, -py], [0, 0, -1]]
  // in units of the image size, px = py = 1/2: the image centre, which is
  // W/2 in pixel-edge coordinates.
  camera.fx = std::abs(normalised_k_(0, 0)) * width_;
  camera.fy = std::abs(normalised_k_(1, 1)) * height_;
  camera.cx = std::abs(normalised_k_(0, 2)) * width_;
  camera.cy = std::abs(normalised_k_(1, 2)) * height_;
  Eigen::Vector3d position;
  Eigen::Matrix<double, 4, 1> wxyz;
  AtPointer(metadata_file_, "/camera/positions" + at, [&] {
    position = JsonNumbers<3>(camera_.at("positions").at(index));
    return 0;
  });
  AtPointer(metadata_file_, "/camera/quaternions" + at, [&] {
    wxyz = JsonNumbers<4>(camera_.at("quaternions").at(index));
    return 0;
  });
  if (!(std::abs(wxyz.norm() - 1) < 1e-3))
    throw Error("not a unit quaternion", Location(metadata_file_, "/camera/quaternions" + at));
  const Eigen::Matrix3d world_from_blender_cam =
      Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized().toRotationMatrix();
  // The Blender camera's x, y, z are the OpenCV camera's x, -y, -z.
  const Eigen::Matrix3d world_from_cam =
      world_from_blender_cam * Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix();
  frame.camera.cam_from_world_rotation = world_from_cam.transpose();
  frame.camera.cam_from_world_translation = -(world_from_cam.transpose() * position);

  frame.flat["rgb"] = ReadSrgbLayer(root_->File(scene_ / FrameFile("rgba", index, "png")),
                                    width_,
                                    height_,
                                    "metadata.json resolution");

  const fs::path depth_path = root_->File(scene_ / FrameFile("depth", index, "tiff"));
  const cv::Mat depth_tiff = ReadImage(depth_path, cv::IMREAD_UNCHANGED);
  if (depth_tiff.empty() || depth_tiff.type() != CV_32FC1 || depth_tiff.cols != width_ ||
      depth_tiff.rows != height_)
    throw Error(
        "not a " + std::to_string(width_) + "x" + std::to_string(height_) + " float32 depth TIFF",
        Location(depth_path.string()));
  exr::FlatImage& depth = frame.flat["depth"] = exr::FlatImage(width_, height_);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) {
      const float d = depth_tiff.at<float>(j, i);
      // Blender writes its far value for the background, never NaN: a NaN is
      // a broken file, not sky.
      if (d < 0 || std::isnan(d))
        throw Error(std::isnan(d) ? "NaN depth" : "negative depth",
                    Location::Pixel(depth_path.string(), index, i, j));
      z[depth.Index(i, j)] = d >= kBackgroundDepth ? std::numeric_limits<float>::infinity() : d;
    }

  const fs::path segmentation_path = root_->File(scene_ / FrameFile("segmentation", index, "png"));
  const IndexImage segmentation = ReadIndexedPng(segmentation_path);
  if (segmentation.width != width_ || segmentation.height != height_)
    throw Error("not " + std::to_string(width_) + "x" + std::to_string(height_),
                Location(segmentation_path.string()));
  exr::FlatImage& instances = frame.flat["instanceid"] = exr::FlatImage(width_, height_);
  exr::FlatImage& classes = frame.flat["classid"] = exr::FlatImage(width_, height_);
  std::vector<uint32_t>& instance = instances.AddChannel("id", exr::PixelType::kUint).uints;
  std::vector<uint32_t>& klass = classes.AddChannel("id", exr::PixelType::kUint).uints;
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) {
      const uint8_t v = segmentation.index[static_cast<size_t>(j) * width_ + i];
      if (v == 0) continue;
      if (v > identities_.size())
        throw Error("segmentation index " + std::to_string(v) + " but only " +
                        std::to_string(identities_.size()) + " instances in metadata.json",
                    Location::Pixel(segmentation_path.string(), index, i, j));
      instance[instances.Index(i, j)] = v;
      klass[classes.Index(i, j)] = identities_[v - 1].class_id;
    }

  for (size_t n = 0; n < identities_.size(); ++n) {
    ObjectIdentity target;
    target.instance_id = static_cast<uint32_t>(n + 1);
    target.class_id = identities_[n].class_id;
    target.name = identities_[n].name;
    target.asset = identities_[n].asset;
    target.obb = ObbFromCorners(instances_[n].at("bboxes_3d").at(index),
                                metadata_file_,
                                "/instances/" + std::to_string(n) + "/bboxes_3d" + at);
    frame.targets.push_back(target);
  }
  return frame;
}

}  // namespace lsds::import
