#include "importers/bop/bop_importer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "importers/derived_truth.h"
#include "importers/source_json.h"
#include "importers/source_png.h"
#include "libs/imaging/image_codecs.h"
#include "libs/util/error.h"
#include "libs/util/output_guard.h"

namespace lsds::import {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

Eigen::Matrix3d Matrix3(const json& j) {
  if (!j.is_array() || j.size() != 9)
    throw json::type_error::create(302, "expected 9 numbers, row-major", &j);
  Eigen::Matrix3d m;
  for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = j.at(k).get<double>();
  return m;
}
Eigen::Vector3d Vector3(const json& j) {
  if (!j.is_array() || j.size() != 3) throw json::type_error::create(302, "expected 3 numbers", &j);
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

std::string Stem(int64_t id) {
  char text[32];
  std::snprintf(text, sizeof text, "%06lld", static_cast<long long>(id));
  return text;
}

bool IsRotation(const Eigen::Matrix3d& r) {
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-5 &&
         r.determinant() > 0;
}

}  // namespace

SourceDescription BopImporter::Open(const fs::path& source, const ImportOptions& options) {
  scene_ = source;
  root_.emplace(source, options.allow_links_outside);
  camera_file_ = root_->File(source / "scene_camera.json").string();
  gt_file_ = root_->File(source / "scene_gt.json").string();
  if (!fs::is_regular_file(camera_file_))
    throw Error("not a BOP scene folder: no scene_camera.json", Location(source.string()));
  cameras_ = ParseJsonFile(camera_file_);
  gts_ = ParseJsonFile(gt_file_);
  // visib_fract, BlenderProc's visibility of each object (scene_gt_info.json,
  // written with calc_mask_info_coco), is the collection's visibility.
  gt_info_file_ = root_->File(source / "scene_gt_info.json").string();
  if (fs::exists(gt_info_file_)) gt_info_ = ParseJsonFile(gt_info_file_);
  if (!cameras_.is_object() || cameras_.empty())
    throw Error("expected an object of image ids", Location(camera_file_));
  for (const auto& [key, value] : cameras_.items()) {
    const std::optional<int64_t> id = ParseInteger(key, 0, std::numeric_limits<int64_t>::max());
    if (!id)
      throw Error("key '" + Excerpt(key, 40) + "' is not an image id (an integer >= 0)",
                  Location(camera_file_, (json::json_pointer() / key).to_string()));
    image_ids_.emplace_back(*id, key);
  }
  std::sort(image_ids_.begin(), image_ids_.end());
  // The dataset's models (default: ../../models/models_info.json of a split's
  // scene folder), confined to the dataset's folder.
  std::optional<ConfinedFolder> dataset;
  if (options.objects.empty())
    dataset.emplace(CanonicalPath(source).parent_path().parent_path(), options.allow_links_outside);
  const fs::path models_file = options.objects.empty()
                                   ? dataset->File(dataset->root() / "models" / "models_info.json")
                                   : options.objects;
  const json models = ParseJsonFile(models_file);
  for (const auto& [key, info] : models.items()) {
    const std::string where = (json::json_pointer() / key).to_string();
    ModelBox box;
    AtPointer(models_file.string(), where, [&, &info = info] {  // clang < 16: no bindings in [&]
      box.min_mm = {info.at("min_x").get<double>(),
                    info.at("min_y").get<double>(),
                    info.at("min_z").get<double>()};
      box.size_mm = {info.at("size_x").get<double>(),
                     info.at("size_y").get<double>(),
                     info.at("size_z").get<double>()};
      return 0;
    });
    // Keys are obj_ids, ids of lsds' 32-bit classes: 4294967297 must not wrap
    // onto class 1.
    const std::optional<int64_t> obj_id =
        ParseInteger(key, 1, std::numeric_limits<uint32_t>::max());
    if (!obj_id)
      throw Error("key '" + Excerpt(key, 40) + "' is not an obj_id in [1, 4294967295]",
                  Location(models_file.string(), where));
    if (!(box.size_mm.minCoeff() >= 0))
      throw Error("sizes must be >= 0", Location(models_file.string(), where));
    models_[static_cast<uint32_t>(*obj_id)] = box;
    classes_.push_back({static_cast<uint32_t>(*obj_id), "obj_" + Stem(*obj_id)});
  }
  // The image size, from the first depth image.
  const fs::path first = root_->File(source / "depth" / (Stem(image_ids_[0].first) + ".png"));
  const cv::Mat depth = ReadImage(first, cv::IMREAD_UNCHANGED);
  if (depth.empty() || depth.type() != CV_16UC1)
    throw Error("not a 16-bit greyscale depth PNG", Location(first.string()));
  width_ = depth.cols, height_ = depth.rows;

  SourceDescription description;
  description.classes = classes_;
  description.frame_count = static_cast<int64_t>(image_ids_.size());
  description.semantics = {"rgb", "classid", "instanceid", "depth"};
  description.depth_kind = DepthKind::kPlanar;
  description.truth_origin = {{"rgb", "imported"},
                              {"instanceid", "imported"},
                              {"classid", "imported"},
                              {"depth", "imported"},
                              {"camera", "imported"},
                              {"obb", "derived"}};
  if (gt_info_) description.truth_origin["visibility"] = "imported";
  description.source_conventions = {
      {"world_frame", "Blender world (z up), declared ENU"},
      {"length_unit", "mm"},
      {"principal_point", "pixel-centre (cx = (W-1)/2 centred), +0.5 to edge"},
      {"depth", "16-bit PNG, mm = value * depth_scale, 65535 (BlenderProc's clip) and 0 = none"},
      {"visibility", "scene_gt_info.json visib_fract"},
      {"converted_to", "ENU m"}};
  return description;
}

namespace {

constexpr uint16_t kBopDepthClip = 65535;

// The depth layer from BOP's 16-bit PNG: depth_scale millimetres per unit.
// 65535 is BlenderProc's clip value for the sky and everything beyond the
// range (BopWriterUtility.py save_depth: `im[im > 65535] = 65535`) and 0 BOP's
// "no measurement" of real sensors: both are no depth (+inf), not a surface.
exr::FlatImage ReadBopDepth(const fs::path& depth_path, int width, int height, double depth_scale) {
  const cv::Mat depth_png = ReadImage(depth_path, cv::IMREAD_UNCHANGED);
  if (depth_png.empty() || depth_png.type() != CV_16UC1 || depth_png.cols != width ||
      depth_png.rows != height)
    throw Error(
        "not a " + std::to_string(width) + "x" + std::to_string(height) + " 16-bit depth PNG",
        Location(depth_path.string()));
  exr::FlatImage depth(width, height);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const uint16_t v = depth_png.at<uint16_t>(j, i);
      z[depth.Index(i, j)] = v == 0 || v == kBopDepthClip
                                 ? std::numeric_limits<float>::infinity()
                                 : static_cast<float>(v * depth_scale / 1000.0);
    }
  return depth;
}

// Object g's visible mask into the id layers. BlenderProc's visible masks
// (bop_toolkit visibility.py, mode bop19: the object is visible where its own
// distance is within `delta`, 15 mm by default, of the scene's) overlap where
// objects touch; the pixels several masks claim are collected in `claims`.
void PaintVisibleMask(const fs::path& mask_path,
                      size_t g,
                      const ObjectIdentity& target,
                      exr::FlatImage* instances,
                      exr::FlatImage* classes,
                      std::map<size_t, std::vector<size_t>>* claims) {
  const int width = instances->width(), height = instances->height();
  std::vector<uint32_t>& instance = instances->Get("id").uints;
  std::vector<uint32_t>& klass = classes->Get("id").uints;
  const cv::Mat mask = ReadImage(mask_path, cv::IMREAD_GRAYSCALE);
  if (mask.empty() || mask.cols != width || mask.rows != height)
    throw Error(
        "missing, unreadable or not " + std::to_string(width) + "x" + std::to_string(height),
        Location(mask_path.string()));
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      if (mask.at<uint8_t>(j, i) == 0) continue;
      const size_t p = instances->Index(i, j);
      if (instance[p] != 0) {
        std::vector<size_t>& claimed = (*claims)[p];
        if (claimed.empty()) claimed.push_back(instance[p] - 1);
        claimed.push_back(g);
        continue;
      }
      instance[p] = target.instance_id;
      klass[p] = target.class_id;
    }
}

// A pixel several visible masks claim goes to the object whose surface the
// depth shows: the one whose box the pixel's ray enters nearest the measured
// distance; boxes entered within the depth's rounding (half a unit of
// depth_scale) of it are the same distance, and the nearest of them is in
// front. With no depth, the nearest box. Exact for box-shaped models; the box
// is the model's tight bounding box otherwise.
void ResolveClaimsByDepth(const std::map<size_t, std::vector<size_t>>& claims,
                          const std::vector<ObjectIdentity>& targets,
                          const CameraTruth& camera,
                          const exr::FlatImage& depth,
                          double depth_scale_mm,
                          exr::FlatImage* instances,
                          exr::FlatImage* classes) {
  const Rigid3d world_from_cam = CamFromWorld(camera).Inverse();
  const std::vector<float>& z = depth.Get("Z").floats;
  for (const auto& [p, candidates] : claims) {
    const int i = static_cast<int>(p % depth.width()), j = static_cast<int>(p / depth.width());
    const Eigen::Vector3d ray = camera.intrinsics.RayThroughPixelCenter(i, j);  // z = 1
    const double measured = static_cast<double>(z[p]) * ray.norm();             // planar -> ray
    const double rounding = 0.5e-3 * depth_scale_mm * ray.norm() + 1e-9;
    const Eigen::Vector3d direction = (world_from_cam.rotation * ray).normalized();
    // (distance from the measured surface beyond the rounding, entry): the
    // least wins, so among boxes within the rounding the nearest one.
    std::pair<double, double> best{std::numeric_limits<double>::infinity(), 0};
    size_t owner = candidates.front();
    for (const size_t g : candidates) {
      const std::optional<double> entry =
          RayEntersBox(*targets[g].obb, world_from_cam.translation, direction);
      if (!entry) continue;
      const double miss =
          std::isfinite(measured) ? std::max(0.0, std::abs(*entry - measured) - rounding) : 0.0;
      if (std::make_pair(miss, *entry) < best) best = {miss, *entry}, owner = g;
    }
    instances->Get("id").uints[p] = targets[owner].instance_id;
    classes->Get("id").uints[p] = targets[owner].class_id;
  }
}

}  // namespace

SourceFrame BopImporter::ReadFrame(int64_t index) {
  const int64_t id = image_ids_.at(static_cast<size_t>(index)).first;
  const std::string& key = image_ids_.at(static_cast<size_t>(index)).second;
  const std::string where = (json::json_pointer() / key).to_string();
  SourceFrame frame;
  frame.time = static_cast<double>(index);  // BOP images are independent views
  frame.sequence = scene_.filename().string();
  frame.shot = index;
  Eigen::Matrix3d k, r_w2c;
  Eigen::Vector3d t_w2c_mm;
  double depth_scale = 1;
  AtPointer(camera_file_, where, [&] {
    const json& c = cameras_.at(key);
    k = Matrix3(c.at("cam_K"));
    r_w2c = Matrix3(c.at("cam_R_w2c"));
    t_w2c_mm = Vector3(c.at("cam_t_w2c"));
    depth_scale = c.value("depth_scale", 1.0);
    return 0;
  });
  if (!IsRotation(r_w2c))
    throw Error("cam_R_w2c is not a rotation", Location(camera_file_, where + "/cam_R_w2c"));
  PinholeCamera& camera = frame.camera.intrinsics;
  camera.width = width_, camera.height = height_;
  camera.fx = k(0, 0), camera.fy = k(1, 1);
  // BOP's principal point is in pixel-centre coordinates (pixel i's centre is
  // i); lsds's in pixel-edge ones (its centre is i + 0.5).
  camera.cx = k(0, 2) + 0.5, camera.cy = k(1, 2) + 0.5;
  frame.camera.cam_from_world_rotation = r_w2c;
  frame.camera.cam_from_world_translation = t_w2c_mm / 1000.0;
  const Eigen::Matrix3d world_from_cam = r_w2c.transpose();
  const Eigen::Vector3d centre_mm = -(world_from_cam * t_w2c_mm);

  frame.flat["rgb"] = ReadSrgbLayer(
      root_->File(scene_ / "rgb" / (Stem(id) + ".png")), width_, height_, "the depth images' size");

  const fs::path depth_path = root_->File(scene_ / "depth" / (Stem(id) + ".png"));
  frame.flat["depth"] = ReadBopDepth(depth_path, width_, height_, depth_scale);

  exr::FlatImage& instances = frame.flat["instanceid"] = exr::FlatImage(width_, height_);
  exr::FlatImage& classes = frame.flat["classid"] = exr::FlatImage(width_, height_);
  instances.AddChannel("id", exr::PixelType::kUint);
  classes.AddChannel("id", exr::PixelType::kUint);
  std::map<size_t, std::vector<size_t>> claims;  // pixel -> gt indices of its masks
  const json gts = AtPointer(gt_file_, where, [&] { return gts_.at(key); });
  if (!gts.is_array()) throw Error("expected an array of objects", Location(gt_file_, where));
  for (size_t g = 0; g < gts.size(); ++g) {
    const std::string at = where + "/" + std::to_string(g);
    const json& gt = gts.at(g);
    const uint32_t obj_id = AtPointer(
        gt_file_, at + "/obj_id", [&] { return IdAt(gt.at("obj_id"), gt_file_, at + "/obj_id"); });
    const auto model = models_.find(obj_id);
    if (model == models_.end())
      throw Error("obj_id " + std::to_string(obj_id) + " is not in models_info.json",
                  Location(gt_file_, at + "/obj_id"));
    const Eigen::Matrix3d r_m2c =
        AtPointer(gt_file_, at + "/cam_R_m2c", [&] { return Matrix3(gt.at("cam_R_m2c")); });
    const Eigen::Vector3d t_m2c =
        AtPointer(gt_file_, at + "/cam_t_m2c", [&] { return Vector3(gt.at("cam_t_m2c")); });
    if (!IsRotation(r_m2c))
      throw Error("cam_R_m2c is not a rotation", Location(gt_file_, at + "/cam_R_m2c"));
    // Instance g + 1: BlenderProc writes a scene's objects in the same order
    // in every image. The class is the model.
    ObjectIdentity target;
    target.instance_id = static_cast<uint32_t>(g + 1);
    target.class_id = obj_id;
    target.name = "obj_" + Stem(obj_id) + "#" + std::to_string(g);
    target.asset = "obj_" + Stem(obj_id);
    const Eigen::Vector3d centre_in_cam =
        r_m2c * (model->second.min_mm + 0.5 * model->second.size_mm) + t_m2c;
    OrientedBox& obb = target.obb.emplace();
    obb.center = (world_from_cam * centre_in_cam + centre_mm) / 1000.0;
    obb.half_extents = 0.5 * model->second.size_mm / 1000.0;
    obb.world_from_box = world_from_cam * r_m2c;
    frame.targets.push_back(target);

    const fs::path mask_path = root_->File(
        scene_ / "mask_visib" / (Stem(id) + "_" + Stem(static_cast<int64_t>(g)) + ".png"));
    PaintVisibleMask(mask_path, g, target, &instances, &classes, &claims);
  }
  ResolveClaimsByDepth(claims,
                       frame.targets,
                       frame.camera,
                       frame.flat.at("depth"),
                       depth_scale,
                       &instances,
                       &classes);
  ReadVisibFract(key, where, &frame);
  return frame;
}

}  // namespace lsds::import

namespace lsds::import {

void BopImporter::ReadVisibFract(const std::string& key,
                                 const std::string& where,
                                 SourceFrame* frame) const {
  if (!gt_info_) return;
  const json& infos =
      AtPointer(gt_info_file_, where, [&]() -> const json& { return gt_info_->at(key); });
  if (!infos.is_array() || infos.size() != frame->targets.size())
    throw Error("expected an array of " + std::to_string(frame->targets.size()) +
                    " entries, one per scene_gt.json entry",
                Location(gt_info_file_, where));
  for (size_t g = 0; g < infos.size(); ++g) {
    const std::string at = where + "/" + std::to_string(g) + "/visib_fract";
    const json& info = infos.at(g);
    if (!info.is_object() || !info.contains("visib_fract") || !info.at("visib_fract").is_number())
      throw Error("expected a number visib_fract", Location(gt_info_file_, at));
    const double fraction = info.at("visib_fract").get<double>();
    if (!(fraction >= 0 && fraction <= 1))
      throw Error("visib_fract must be in [0, 1]", Location(gt_info_file_, at));
    frame->stated[frame->targets[g].instance_id].visibility = fraction;
  }
}

}  // namespace lsds::import
