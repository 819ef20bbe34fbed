#include "importers/replicator/replicator_importer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <set>
#include <tuple>

#include <opencv2/core.hpp>

#include "importers/source_json.h"
#include "importers/source_png.h"
#include "libs/util/error.h"
#include "libs/util/npy.h"
#include "libs/util/strings.h"

namespace lsds::import {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Labels Replicator gives to pixels of no labelled prim.
bool IsBackgroundLabel(const std::string& label) {
  return label == "BACKGROUND" || label == "UNLABELLED" || label.empty();
}

// "(r, g, b, a)" -> packed RGBA.
bool ParseColourKey(const std::string& key, uint32_t* rgba) {
  static const std::regex pattern(R"(\(\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*\))");
  std::smatch m;
  if (!std::regex_match(key, m, pattern)) return false;
  uint32_t packed = 0;
  for (int c = 1; c <= 4; ++c) {
    const std::optional<int64_t> v = ParseInteger(m[c].str(), 0, 255);
    if (!v) return false;
    packed = (packed << 8) | static_cast<uint32_t>(*v);
  }
  *rgba = packed;
  return true;
}

// The class of a semantics entry {"class": "a,b"}: its first label.
std::string ClassLabel(const json& semantics) {
  if (!semantics.is_object() || !semantics.contains("class")) return "";
  std::string label = semantics.at("class").get<std::string>();
  return label.substr(0, label.find(','));
}

// A row-major 4x4 USD matrix (row vectors: p_row * M) as the column-vector
// matrix, its transpose.
Eigen::Matrix4d ColumnMatrix(const Eigen::Matrix<double, 16, 1>& row_major) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = row_major[c * 4 + r];
  return m;
}

}  // namespace

fs::path ReplicatorImporter::Path(const std::string& annotator,
                                  const std::string& stem,
                                  int64_t index,
                                  const std::string& ext) const {
  const FrameFiles& frame = frames_.at(static_cast<size_t>(index));
  const Product& product = products_.at(frame.product);
  const fs::path folder = product.annotator_folders ? product.folder / annotator : product.folder;
  return root_->File(folder / (product.file_prefix + stem + "_" + frame.id + "." + ext));
}

// BasicWriter.write(): rgb_{sequence_id}{frame_id:0{padding}}.png, where each on_time trigger
// prefixes sequence_id with "{call_count}_" and the frame number restarts with each sequence.
void ReplicatorImporter::FindFrames(const Product& product, size_t product_index) {
  static const std::regex rgb_name(R"(rgb_((?:\d+_)*)(\d+)\.png)");
  const fs::path folder = product.annotator_folders ? product.folder / "rgb" : product.folder;
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::smatch m;
    const std::string file_name = entry.path().filename().string();
    if (file_name.rfind(product.file_prefix, 0) != 0) continue;
    const std::string name = file_name.substr(product.file_prefix.size());
    if (!std::regex_match(name, m, rgb_name)) continue;
    FrameFiles frame;
    frame.product = product_index;
    frame.trigger_prefix = m[1].str();
    frame.id = m[1].str() + m[2].str();
    std::string counts = frame.trigger_prefix;
    for (size_t at = counts.find('_'); at != std::string::npos; at = counts.find('_')) {
      const std::optional<int64_t> count =
          ParseInteger(counts.substr(0, at), 0, std::numeric_limits<int64_t>::max());
      if (!count)
        throw Error("a trigger count is beyond 2^63 - 1", Location(entry.path().string()));
      frame.order.push_back(*count);
      counts.erase(0, at + 1);
    }
    const std::optional<int64_t> number =
        ParseInteger(m[2].str(), 0, std::numeric_limits<int64_t>::max());
    if (!number)
      throw Error("the frame number is beyond 2^63 - 1", Location(entry.path().string()));
    frame.order.push_back(*number);
    frames_.push_back(std::move(frame));
  }
}

// One product: its files here, or in annotator folders (rgb/, camera_params/, ...) here.
// Several: BasicWriter's default (use_common_output_dir False) puts each product's files in
// <product>/<annotator>/.
void ReplicatorImporter::FindProducts(const fs::path& source) {
  fs::path source_path = fs::absolute(source).lexically_normal();
  if (source_path.filename().empty()) source_path = source_path.parent_path();  // "folder/"
  const std::string source_name = source_path.filename().string();
  static const std::regex any_rgb(R"(rgb_(\d+_)*\d+\.png)");
  bool flat = false;
  for (const auto& entry : fs::directory_iterator(source))
    flat = flat || std::regex_match(entry.path().filename().string(), any_rgb);
  if (flat) {
    products_.push_back({source_name, source, false, ""});
  } else if (fs::is_directory(source / "rgb")) {
    // One product's annotator folders (rgb/rgb_0000.png), or several products' files in
    // common annotator folders (use_common_output_dir: rgb/<product>_rgb_0000.png).
    static const std::regex prefixed_rgb(R"((.+_)rgb_(\d+_)*\d+\.png)");
    std::set<std::string> prefixes;
    bool own = false;
    for (const auto& entry : fs::directory_iterator(source / "rgb")) {
      const std::string name = entry.path().filename().string();
      std::smatch m;
      if (std::regex_match(name, any_rgb)) {
        own = true;
      } else if (std::regex_match(name, m, prefixed_rgb)) {
        prefixes.insert(m[1].str());
      }
    }
    if (own || prefixes.empty()) {
      products_.push_back({source_name, source, true, ""});
    } else {
      for (const std::string& prefix : prefixes)
        products_.push_back({prefix.substr(0, prefix.size() - 1), source, true, prefix});
    }
  } else {
    std::vector<fs::path> folders;
    for (const auto& entry : fs::directory_iterator(source))
      if (entry.is_directory() && fs::is_directory(entry.path() / "rgb"))
        folders.push_back(entry.path());
    std::sort(folders.begin(), folders.end());
    for (const fs::path& folder : folders)
      products_.push_back({folder.filename().string(), folder, true, ""});
  }
}

// The depth and the instance segmentation, from the first frame's files.
void ReplicatorImporter::FindLayers() {
  if (fs::exists(Path("distance_to_image_plane", "distance_to_image_plane", 0, "npy"))) {
    depth_stem_ = "distance_to_image_plane", depth_kind_ = DepthKind::kPlanar;
  } else if (fs::exists(Path("distance_to_camera", "distance_to_camera", 0, "npy"))) {
    depth_stem_ = "distance_to_camera", depth_kind_ = DepthKind::kPerspective;
  }
  has_instances_ =
      fs::exists(Path("instance_segmentation", "instance_segmentation_mapping", 0, "json"));
  if (!has_instances_ &&
      !fs::exists(Path("bounding_box_3d", "bounding_box_3d_labels", 0, "json")) &&
      !fs::exists(Path("bounding_box_2d_tight", "bounding_box_2d_tight_labels", 0, "json")))
    throw Error(
        "neither instance_segmentation (with its mappings) nor bounding_box_3d nor "
        "bounding_box_2d_tight for the first frame: no objects to import",
        Location(Path("rgb", "rgb", 0, "png").string()));
}

// The prim paths and class labels of every frame's mappings.
struct ReplicatorImporter::PrimLabels {
  std::set<std::string> prims, classes;
  std::map<std::string, std::string> class_label_of_prim;

  void Add(const std::string& prim, const std::string& label) {
    prims.insert(prim);
    if (!label.empty()) {
      classes.insert(label);
      class_label_of_prim[prim] = label;
    }
  }
};

void ReplicatorImporter::ScanInstanceMappings(int64_t index, PrimLabels* labels) const {
  const fs::path mapping_path =
      Path("instance_segmentation", "instance_segmentation_mapping", index, "json");
  const fs::path semantics_path =
      Path("instance_segmentation", "instance_segmentation_semantics_mapping", index, "json");
  const json mapping = has_instances_ ? ParseJsonFile(mapping_path) : json::object();
  const json semantics = has_instances_ ? ParseJsonFile(semantics_path) : json::object();
  for (const auto& [key, prim] : mapping.items()) {
    const std::string where = (json::json_pointer() / key).to_string();
    const std::string path = StringAt(prim, mapping_path.string(), where);
    if (IsBackgroundLabel(path)) continue;
    const std::string label = AtPointer(
        semantics_path.string(), where, [&, &key = key] { return ClassLabel(semantics.at(key)); });
    labels->Add(path, label);
  }
}

// The prim paths and class labels of one frame's box records, in record order: bounding_box_3d
// or bounding_box_2d_tight, which BasicWriter's _write_bounding_box_data writes alike (the
// annotator's records with semanticId, its idToLabels as _labels and its primPaths as
// _prim_paths). None where the frame has no such records.
std::vector<std::pair<std::string, std::string>> ReplicatorImporter::ScanBoxes(
    const std::string& annotator, int64_t index) const {
  std::vector<std::pair<std::string, std::string>> rows;
  const fs::path boxes_labels = Path(annotator, annotator + "_labels", index, "json");
  if (!fs::exists(boxes_labels)) return rows;
  const json label_of_id = ParseJsonFile(boxes_labels);
  const fs::path prim_paths_file = Path(annotator, annotator + "_prim_paths", index, "json");
  const json prim_paths = ParseJsonFile(prim_paths_file);
  const fs::path boxes_path = Path(annotator, annotator, index, "npy");
  const NpyArray boxes = ReadNpy(boxes_path);
  const NpyField& semantic_id = boxes.Field("semanticId", boxes_path.string());
  if (!prim_paths.is_array() || prim_paths.size() != static_cast<size_t>(boxes.size()))
    throw Error("expected one prim path per box (" + std::to_string(boxes.size()) + ")",
                Location(prim_paths_file.string()));
  for (int64_t row = 0; row < boxes.size(); ++row) {
    const std::string path =
        StringAt(prim_paths.at(row), prim_paths_file.string(), "/" + std::to_string(row));
    const double semantic = boxes.Get(row, semantic_id);
    if (!(semantic >= 0 && semantic <= std::numeric_limits<uint32_t>::max()) ||
        semantic != std::floor(semantic))
      throw Error("semanticId of row " + std::to_string(row) + " is " + FormatNumber(semantic) +
                      ", not an id in [0, 4294967295]",
                  Location(boxes_path.string()));
    const std::string id = std::to_string(static_cast<int64_t>(semantic));
    const std::string label =
        AtPointer(boxes_labels.string(), "/" + id, [&] { return ClassLabel(label_of_id.at(id)); });
    rows.emplace_back(path, label);
  }
  return rows;
}

// Instance ids and classes hold across frames: prim paths and class labels numbered in
// sorted order.
void ReplicatorImporter::NumberPrims(const PrimLabels& labels, SourceDescription* description) {
  uint32_t next = 1;
  for (const std::string& c : labels.classes) {
    class_ids_[c] = next;
    description->classes.push_back({next++, c});
  }
  next = 1;
  for (const std::string& p : labels.prims) {
    instance_of_prim_[p] = next++;
    const auto label = labels.class_label_of_prim.find(p);
    class_of_prim_[p] =
        label == labels.class_label_of_prim.end() ? 0 : class_ids_.at(label->second);
  }
}

// The layers, their origin and the source's conventions.
void ReplicatorImporter::DescribeTruth(const ImportOptions& options,
                                       SourceDescription* description) const {
  description->semantics = {"rgb"};
  description->truth_origin = {{"rgb", "imported"}, {"camera", "imported"}, {"obb", "imported"}};
  if (has_instances_) {
    description->semantics.insert(description->semantics.end(), {"classid", "instanceid"});
    description->truth_origin["instanceid"] = description->truth_origin["classid"] = "imported";
  } else {
    // The writer's own 2D truth (bounding_box_2d_tight), where it wrote it; no pixel counts.
    const bool tight = fs::exists(Path("bounding_box_2d_tight", "bounding_box_2d_tight", 0, "npy"));
    description->truth_origin["bbox"] = tight ? "imported" : "absent";
    description->truth_origin["visibility"] = "imported";
    description->truth_origin["visible_pixels"] = "absent";
    description->warnings.push_back(
        "no instance_segmentation: no instanceid and classid layers; the objects are the "
        "boxes, their visibility 1 - occlusionRatio" +
        std::string(tight ? ", their box bounding_box_2d_tight's" : ", with no visible 2D box"));
  }
  if (!depth_stem_.empty()) description->semantics.push_back("depth");
  description->depth_kind = depth_kind_;
  if (!depth_stem_.empty()) description->truth_origin["depth"] = "imported";
  description->source_conventions = {
      {"world_frame",
       options.up_axis == "y" ? "USD stage, y up (--up-axis y), to ENU (x, -z, y)"
                              : "USD stage, z up, declared ENU"},
      {"length_unit", "scene units * metersPerSceneUnit"},
      {"camera_frame", "USD/OpenGL camera: looks down -Z, +Y up"},
      {"matrices", "row-major, row vectors (p_row * M)"},
      {"depth", depth_stem_.empty() ? "none" : depth_stem_ + " (.npy float32)"},
      {"converted_to", "ENU m, OpenCV camera, pixel-edge intrinsics"}};
}

SourceDescription ReplicatorImporter::Open(const fs::path& source, const ImportOptions& options) {
  root_.emplace(source, options.allow_links_outside);
  if (options.up_axis == "y") {
    // Y-up stage to ENU: x stays, stage -z is north, stage y is up.
    enu_from_stage_ << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  } else if (options.up_axis != "z" && !options.up_axis.empty()) {
    throw Error("--up-axis must be z or y, not '" + options.up_axis + "'");
  }
  FindProducts(source);
  for (size_t p = 0; p < products_.size(); ++p) FindFrames(products_[p], p);
  if (frames_.empty())
    throw Error(
        "not a Replicator BasicWriter folder: no rgb_NNNN.png here, in rgb/ or in "
        "<render product>/rgb/",
        Location(source.string()));
  std::sort(frames_.begin(), frames_.end(), [](const FrameFiles& a, const FrameFiles& b) {
    return std::tie(a.product, a.order) < std::tie(b.product, b.order);
  });
  FindLayers();
  PrimLabels labels;
  // The tight 2D boxes of prims with no 3D box in the same frame, by class label: objects
  // without a 3D box (format.md "Objects without a 3D box"), said once in a warning.
  std::map<std::string, int64_t> boxes_2d_only;
  for (size_t f = 0; f < frames_.size(); ++f) {
    const auto index = static_cast<int64_t>(f);
    ScanInstanceMappings(index, &labels);
    std::set<std::string> with_3d;
    for (const auto& [prim, label] : ScanBoxes("bounding_box_3d", index)) {
      labels.Add(prim, label);
      with_3d.insert(prim);
    }
    for (const auto& [prim, label] : ScanBoxes("bounding_box_2d_tight", index)) {
      labels.Add(prim, label);
      if (!with_3d.count(prim)) ++boxes_2d_only[label.empty() ? "(no label)" : label];
    }
  }
  SourceDescription description;
  NumberPrims(labels, &description);
  description.frame_count = static_cast<int64_t>(frames_.size());
  DescribeTruth(options, &description);
  for (const auto& [label, count] : boxes_2d_only)
    description.warnings.push_back(
        std::to_string(count) + " bounding_box_2d_tight box(es) of '" + label +
        "' have no bounding_box_3d box: objects without a 3D box (no obb, no bbox_projected); " +
        "their visibility is 1 - the 2D record's occlusionRatio, their in_frame not measured (1)" +
        (has_instances_ ? "" : "; with no instance segmentation, no visible_pixels either"));
  return description;
}

namespace {

// The stages of ReplicatorImporter::ReadFrame: the camera (pose and intrinsics), the RGB, the
// depth from the distance array, the id layers from the instance segmentation, and the
// targets from the 3D boxes.

// The frame's camera from camera_params: the OpenGL view and projection to an OpenCV camera
// in ENU metres. Returns the scene's metres per unit.
double ReadCamera(const fs::path& camera_path,
                  const Eigen::Matrix3d& enu_from_stage,
                  CameraTruth* camera_truth) {
  const json params = ParseJsonFile(camera_path);
  const std::string camera_file = camera_path.string();
  Eigen::Matrix<double, 16, 1> view, projection;
  int width = 0, height = 0;
  double meters_per_unit = 1;
  AtPointer(camera_file, "/cameraViewTransform", [&] {
    view = JsonNumbers<16>(params.at("cameraViewTransform"));
    return 0;
  });
  AtPointer(camera_file, "/cameraProjection", [&] {
    projection = JsonNumbers<16>(params.at("cameraProjection"));
    return 0;
  });
  AtPointer(camera_file, "/renderProductResolution", [&] {
    const json& resolution = params.at("renderProductResolution");
    width = IntegerAt<int>(resolution.at(0), camera_file, "/renderProductResolution/0");
    height = IntegerAt<int>(resolution.at(1), camera_file, "/renderProductResolution/1");
    return 0;
  });
  AtPointer(camera_file, "/metersPerSceneUnit", [&] {
    meters_per_unit = params.value("metersPerSceneUnit", 1.0);
    return 0;
  });
  if (width < 1 || height < 1 || !(meters_per_unit > 0))
    throw Error("resolution and metersPerSceneUnit must be positive", Location(camera_file));
  const Eigen::Matrix4d gl_cam_from_stage = ColumnMatrix(view);
  const Eigen::Matrix3d r = gl_cam_from_stage.topLeftCorner<3, 3>();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
      r.determinant() < 0)
    throw Error("not a rigid view matrix", Location(camera_file, "/cameraViewTransform"));
  // OpenGL camera (x right, y up, looking down -z) to OpenCV: y, z negated;
  // the stage to ENU and scene units to metres.
  const Eigen::Matrix3d cv_from_gl = Eigen::Vector3d(1, -1, -1).asDiagonal();
  camera_truth->cam_from_world_rotation = cv_from_gl * r * enu_from_stage.transpose();
  camera_truth->cam_from_world_translation =
      meters_per_unit * (cv_from_gl * gl_cam_from_stage.topRightCorner<3, 1>());
  // The OpenGL projection: x_ndc = P00 x / -z - P02 and u = (x_ndc + 1) W / 2
  // (u from the left edge), y_ndc = P11 y / -z - P12 and v = (1 - y_ndc) H / 2
  // (v from the top edge).
  const Eigen::Matrix4d p = ColumnMatrix(projection);
  PinholeCamera& camera = camera_truth->intrinsics;
  camera.width = width, camera.height = height;
  camera.fx = 0.5 * width * p(0, 0);
  camera.fy = 0.5 * height * p(1, 1);
  camera.cx = 0.5 * width * (1 - p(0, 2));
  camera.cy = 0.5 * height * (1 + p(1, 2));
  if (!(camera.fx > 0 && camera.fy > 0))
    throw Error("not a perspective projection", Location(camera_file, "/cameraProjection"));
  return meters_per_unit;
}

// The depth layer from the distance array (scene units to metres; +inf, the sky, stays).
exr::FlatImage ReadDistanceDepth(
    const fs::path& depth_path, int64_t index, int width, int height, double meters_per_unit) {
  const NpyArray distance = ReadNpy(depth_path);
  const bool shape_ok =
      (distance.shape.size() == 2 || (distance.shape.size() == 3 && distance.shape[2] == 1)) &&
      distance.shape[0] == height && distance.shape[1] == width && distance.fields.size() == 1 &&
      distance.fields[0].kind == 'f';
  if (!shape_ok)
    throw Error("expected a float array of shape (" + std::to_string(height) + ", " +
                    std::to_string(width) + ")",
                Location(depth_path.string()));
  exr::FlatImage depth(width, height);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  const NpyField& field = distance.fields[0];
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const double d = distance.Get(static_cast<int64_t>(j) * width + i, field);
      if (d < 0)
        throw Error("negative distance", Location::Pixel(depth_path.string(), index, i, j));
      if (std::isnan(d))
        throw Error("NaN distance", Location::Pixel(depth_path.string(), index, i, j));
      // +inf where no surface: the sky.
      z[depth.Index(i, j)] = std::isfinite(d) ? static_cast<float>(d * meters_per_unit)
                                              : std::numeric_limits<float>::infinity();
    }
  return depth;
}

// Instance segmentation: colour -> prim path -> instance id, and the instance's class.
void ReadInstanceLayers(const fs::path& segmentation_path,
                        const fs::path& mapping_path,
                        int64_t index,
                        const PinholeCamera& camera,
                        const std::map<std::string, uint32_t>& instance_of_prim,
                        const std::map<std::string, uint32_t>& class_of_prim,
                        SourceFrame* frame) {
  const int width = camera.width, height = camera.height;
  const json mapping = ParseJsonFile(mapping_path);
  std::map<uint32_t, uint32_t> instance_of_colour;
  for (const auto& [key, prim] : mapping.items()) {
    uint32_t rgba = 0;
    if (!ParseColourKey(key, &rgba))
      throw Error("expected a colour key \"(r, g, b, a)\"",
                  Location(mapping_path.string(), (json::json_pointer() / key).to_string()));
    const std::string path =
        StringAt(prim, mapping_path.string(), (json::json_pointer() / key).to_string());
    instance_of_colour[rgba] = IsBackgroundLabel(path) ? 0 : instance_of_prim.at(path);
  }
  const cv::Mat colours = ReadRgbaPng(segmentation_path, width, height);
  exr::FlatImage& instances = frame->flat["instanceid"] = exr::FlatImage(width, height);
  exr::FlatImage& classes = frame->flat["classid"] = exr::FlatImage(width, height);
  std::vector<uint32_t>& instance = instances.AddChannel("id", exr::PixelType::kUint).uints;
  std::vector<uint32_t>& klass = classes.AddChannel("id", exr::PixelType::kUint).uints;
  std::map<uint32_t, uint32_t> class_of_instance;
  for (const auto& [prim, id] : instance_of_prim) class_of_instance[id] = class_of_prim.at(prim);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const uint32_t rgba = PackedRgba(colours.at<cv::Vec4b>(j, i));
      const auto found = instance_of_colour.find(rgba);
      if (found == instance_of_colour.end()) {
        throw Error("colour " + RgbaText(rgba) + " is not in " + mapping_path.filename().string(),
                    Location::Pixel(segmentation_path.string(), index, i, j));
      }
      instance[instances.Index(i, j)] = found->second;
      klass[classes.Index(i, j)] = found->second ? class_of_instance.at(found->second) : 0;
    }
}

// One row of bounding_box_3d: local extents and a row-vector local-to-world transform, as an
// OBB in ENU metres.
OrientedBox BoxOfRow(const NpyArray& boxes,
                     int64_t row,
                     const std::string& file,
                     const Eigen::Matrix3d& enu_from_stage,
                     double meters_per_unit) {
  const char* names[6] = {"x_min", "y_min", "z_min", "x_max", "y_max", "z_max"};
  const NpyField& transform_field = boxes.Field("transform", file);
  double extent[6];
  for (int e = 0; e < 6; ++e) extent[e] = boxes.Get(row, boxes.Field(names[e], file));
  Eigen::Matrix<double, 16, 1> t;
  for (int e = 0; e < 16; ++e) t[e] = boxes.Get(row, transform_field, e);
  const Eigen::Matrix4d stage_from_local = ColumnMatrix(t);
  const Eigen::Matrix3d linear = stage_from_local.topLeftCorner<3, 3>();
  const Eigen::Vector3d local_min(extent[0], extent[1], extent[2]);
  const Eigen::Vector3d local_max(extent[3], extent[4], extent[5]);
  OrientedBox obb;
  Eigen::Matrix3d axes;
  for (int a = 0; a < 3; ++a) {
    const double scale = linear.col(a).norm();
    if (!(scale > 0) || !(local_max[a] >= local_min[a]))
      throw Error("degenerate box in row " + std::to_string(row), Location(file));
    axes.col(a) = linear.col(a) / scale;
    obb.half_extents[a] = 0.5 * (local_max[a] - local_min[a]) * scale * meters_per_unit;
  }
  // A mirrored transform (a negative scale, as on some prims of real stages): the box is the
  // same set of points with one axis reversed, since its extent is symmetric about the centre.
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  // float32 records: the axes are orthonormal to 1e-7; make them exactly
  // a rotation.
  obb.world_from_box = enu_from_stage * Eigen::Quaterniond(axes).normalized().toRotationMatrix();
  const Eigen::Vector3d centre_in_stage =
      linear * (0.5 * (local_min + local_max)) + stage_from_local.topRightCorner<3, 1>();
  obb.center = meters_per_unit * (enu_from_stage * centre_in_stage);
  return obb;
}

}  // namespace

// bounding_box_2d_tight: the box of the visible pixels as inclusive pixel indices (x_max and
// y_max the last pixel), and the share of the object occluded. Without instance segmentation the
// box is the object's bbox (with it, the id layer gives the same box). A prim with no 3D box in
// the frame is an object without one (format.md "Objects without a 3D box"), measured on the id
// layer where there is one; its visibility is 1 - the record's occlusionRatio where that is in
// [0, 1] (Replicator writes -1 where it could not tell).
void ReplicatorImporter::ReadTightBoxes(int64_t index, SourceFrame* frame) const {
  const fs::path boxes_path = Path("bounding_box_2d_tight", "bounding_box_2d_tight", index, "npy");
  if (!fs::exists(boxes_path)) return;
  const std::string file = boxes_path.string();
  const NpyArray boxes = ReadNpy(boxes_path);
  const fs::path prim_paths_path =
      Path("bounding_box_2d_tight", "bounding_box_2d_tight_prim_paths", index, "json");
  const json prim_paths = ParseJsonFile(prim_paths_path);
  if (!prim_paths.is_array() || prim_paths.size() != static_cast<size_t>(boxes.size()))
    throw Error("expected one prim path per box (" + std::to_string(boxes.size()) + ")",
                Location(prim_paths_path.string()));
  const NpyField& x_min = boxes.Field("x_min", file);
  const NpyField& y_min = boxes.Field("y_min", file);
  const NpyField& x_max = boxes.Field("x_max", file);
  const NpyField& y_max = boxes.Field("y_max", file);
  const NpyField* occlusion = nullptr;
  for (const NpyField& field : boxes.fields)
    if (field.name == "occlusionRatio") occlusion = &field;
  std::set<uint32_t> with_obb;
  for (const ObjectIdentity& target : frame->targets) with_obb.insert(target.instance_id);
  for (int64_t row = 0; row < boxes.size(); ++row) {
    const std::string path =
        StringAt(prim_paths.at(row), prim_paths_path.string(), "/" + std::to_string(row));
    const uint32_t instance = instance_of_prim_.at(path);  // Open numbered every prim
    const Box2d box{boxes.Get(row, x_min),
                    boxes.Get(row, y_min),
                    boxes.Get(row, x_max) + 1,
                    boxes.Get(row, y_max) + 1};
    if (box.empty()) throw Error("row " + std::to_string(row) + " is an empty box", Location(file));
    if (!has_instances_) frame->stated[instance].bbox = box;
    if (!with_obb.insert(instance).second) continue;
    ObjectIdentity target;
    target.instance_id = instance;
    target.class_id = class_of_prim_.at(path);
    target.name = path;
    frame->targets.push_back(target);
    const double occluded = occlusion != nullptr ? boxes.Get(row, *occlusion) : -1;
    if (occluded >= 0 && occluded <= 1) frame->stated[instance].visibility = 1 - occluded;
  }
}

SourceFrame ReplicatorImporter::ReadFrame(int64_t index) {
  SourceFrame frame;
  const FrameFiles& files = frames_.at(static_cast<size_t>(index));
  // BasicWriter writes no timestamps; randomised frames are independent. Each render product
  // (and each on_time trigger count) is a sequence.
  frame.time = static_cast<double>(index);
  frame.sequence = products_.at(files.product).name;
  if (!files.trigger_prefix.empty())
    frame.sequence += "#" + files.trigger_prefix.substr(0, files.trigger_prefix.size() - 1);
  frame.shot = index;
  const double meters_per_unit = ReadCamera(
      Path("camera_params", "camera_params", index, "json"), enu_from_stage_, &frame.camera);
  const int width = frame.camera.intrinsics.width, height = frame.camera.intrinsics.height;
  frame.flat["rgb"] =
      ReadSrgbLayer(Path("rgb", "rgb", index, "png"), width, height, "renderProductResolution");
  if (!depth_stem_.empty()) {
    frame.flat["depth"] = ReadDistanceDepth(
        Path(depth_stem_, depth_stem_, index, "npy"), index, width, height, meters_per_unit);
  }
  if (has_instances_) {
    ReadInstanceLayers(
        Path("instance_segmentation", "instance_segmentation", index, "png"),
        Path("instance_segmentation", "instance_segmentation_mapping", index, "json"),
        index,
        frame.camera.intrinsics,
        instance_of_prim_,
        class_of_prim_,
        &frame);
  }

  // 3D boxes, when written, are the targets; then the tight 2D boxes (of prims without one too).
  const fs::path boxes_path = Path("bounding_box_3d", "bounding_box_3d", index, "npy");
  if (fs::exists(boxes_path)) {
    const std::string file = boxes_path.string();
    const NpyArray boxes = ReadNpy(boxes_path);
    const fs::path prim_paths_path =
        Path("bounding_box_3d", "bounding_box_3d_prim_paths", index, "json");
    const json prim_paths = ParseJsonFile(prim_paths_path);
    const NpyField& transform_field = boxes.Field("transform", file);
    if (transform_field.count != 16) throw Error("field 'transform' is not 4x4", Location(file));
    const NpyField* occlusion = nullptr;
    for (const NpyField& field : boxes.fields)
      if (field.name == "occlusionRatio") occlusion = &field;
    for (int64_t row = 0; row < boxes.size(); ++row) {
      const OrientedBox obb = BoxOfRow(boxes, row, file, enu_from_stage_, meters_per_unit);
      const std::string path =
          StringAt(prim_paths.at(row), prim_paths_path.string(), "/" + std::to_string(row));
      ObjectIdentity target;
      target.instance_id = instance_of_prim_.at(path);
      target.class_id = class_of_prim_.at(path);
      target.name = path;
      target.obb = obb;
      frame.targets.push_back(target);
      // The renderer's own occluded share; outside [0, 1] (-1, NaN) when it could not tell.
      const double occluded = occlusion != nullptr ? boxes.Get(row, *occlusion) : -1;
      if (!has_instances_ && occluded >= 0 && occluded <= 1)
        frame.stated[target.instance_id].visibility = 1 - occluded;
    }
  }
  ReadTightBoxes(index, &frame);
  return frame;
}

}  // namespace lsds::import
