#include "importers/solo/solo_importer.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <tuple>

#include <opencv2/core.hpp>

#include "importers/source_json.h"
#include "importers/source_png.h"
#include "libs/util/error.h"

namespace lsds::import {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool HasType(const json& element, const char* type) {
  const auto it = element.find("@type");
  if (it == element.end() || !it->is_string()) return false;
  const std::string t = it->get<std::string>();
  const std::string suffix = std::string(".") + type;
  return t.size() >= suffix.size() &&
         t.compare(t.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Unity's world (left-handed: x right/east, y up, z forward/north) to ENU:
// swap y and z. Its own inverse.
Eigen::Matrix3d EnuFromUnity() {
  Eigen::Matrix3d e;
  e << 1, 0, 0, 0, 0, 1, 0, 1, 0;
  return e;
}

// Unity serializes quaternions x, y, z, w (MessageBuilderUtils.ToFloatVector),
// whatever the schema page says.
Eigen::Matrix3d RotationXyzw(const Eigen::Matrix<double, 4, 1>& q,
                             const std::string& file,
                             const std::string& where) {
  if (!(std::abs(q.norm() - 1) < 1e-3))
    throw Error("not a unit quaternion [x, y, z, w]", Location(file, where));
  return Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
}

// The RGB sensor's capture schedule, when sensor_definitions.json has one.
CaptureSchedule ReadCaptureSchedule(const ConfinedFolder& root, const fs::path& source) {
  CaptureSchedule schedule;
  const fs::path path = root.File(source / "sensor_definitions.json");
  if (!fs::is_regular_file(path)) return schedule;
  const json definitions = ParseJsonFile(path);
  const std::string file = path.string();
  const json& sensors = AtPointer(file, "/sensorDefinitions", [&]() -> const json& {
    return definitions.at("sensorDefinitions");
  });
  for (size_t s = 0; s < sensors.size(); ++s) {
    if (!HasType(sensors[s], "RGBCamera")) continue;
    const std::string where = "/sensorDefinitions/" + std::to_string(s);
    AtPointer(file, where, [&] {
      schedule.scheduled = sensors[s].value("captureTriggerMode", "") == "Scheduled";
      schedule.delta_time = sensors[s].value("simulationDeltaTime", 0.0);
      schedule.first_capture_frame = sensors[s].value("firstCaptureFrame", 0.0);
      schedule.frames_between = sensors[s].value("framesBetweenCaptures", int64_t{0});
      return 0;
    });
    if (schedule.scheduled && !(schedule.delta_time > 0 && schedule.frames_between >= 0))
      throw Error("a scheduled sensor needs simulationDeltaTime > 0 and framesBetweenCaptures >= 0",
                  Location(file, where));
    break;
  }
  return schedule;
}

// The labels of annotation_definitions.json's specs, by id.
std::map<uint32_t, std::string> ReadLabelDefinitions(const ConfinedFolder& root,
                                                     const fs::path& source) {
  const fs::path definitions_path = root.File(source / "annotation_definitions.json");
  if (!fs::is_regular_file(definitions_path))
    throw Error("not a SOLO dataset: no annotation_definitions.json", Location(source.string()));
  const json definitions = ParseJsonFile(definitions_path);
  const std::string definitions_file = definitions_path.string();
  std::map<uint32_t, std::string> labels;
  AtPointer(definitions_file, "/annotationDefinitions", [&] {
    const json& list = definitions.at("annotationDefinitions");
    for (size_t d = 0; d < list.size(); ++d) {
      if (!list[d].contains("spec")) continue;
      for (size_t s = 0; s < list[d].at("spec").size(); ++s) {
        const json& spec = list[d].at("spec").at(s);
        if (!spec.contains("label_id")) continue;
        const std::string where =
            "/annotationDefinitions/" + std::to_string(d) + "/spec/" + std::to_string(s);
        const uint32_t id = IdAt(spec.at("label_id"), definitions_file, where + "/label_id");
        if (id < 1)
          throw Error("label_id must be >= 1 (0 is background in lsds)",
                      Location(definitions_file, where + "/label_id"));
        labels[id] = AtPointer(definitions_file, where + "/label_name", [&] {
          return StringAt(spec.at("label_name"), definitions_file, where + "/label_name");
        });
      }
    }
    return 0;
  });
  if (labels.empty())
    throw Error(
        "no label spec (label_id, label_name) in any annotation "
        "definition",
        Location(definitions_file, "/annotationDefinitions"));
  return labels;
}

// What the frames use, read before the import: the label ids of the RGB capture's instances
// and 2D and 3D boxes, and the 2D boxes with no 3D box of the same instance, counted by label
// name.
struct LabelUse {
  std::set<uint32_t> used;
  std::map<std::string, int64_t> boxes_2d_only;
};

// The capture's label ids in `field` of the annotations of type `type`, with their instances.
void CollectLabels(const json& capture,
                   const std::string& at,
                   const char* type,
                   const char* field,
                   const std::string& file,
                   std::vector<std::pair<uint32_t, uint32_t>>* instance_labels) {
  const json annotations = capture.value("annotations", json::array());
  for (size_t a = 0; a < annotations.size(); ++a) {
    if (!HasType(annotations[a], type)) continue;
    const std::string where = at + "/annotations/" + std::to_string(a) + "/" + field;
    const json& values =
        AtPointer(file, where, [&]() -> const json& { return annotations[a].at(field); });
    for (size_t n = 0; n < values.size(); ++n) {
      const std::string w = where + "/" + std::to_string(n);
      instance_labels->emplace_back(
          AtPointer(
              file, w, [&] { return IdAt(values[n].at("instanceId"), file, w + "/instanceId"); }),
          AtPointer(file, w, [&] { return IdAt(values[n].at("labelId"), file, w + "/labelId"); }));
    }
  }
}

LabelUse ScanLabelUse(const std::vector<fs::path>& step_files,
                      const std::map<uint32_t, std::string>& labels) {
  LabelUse use;
  for (const fs::path& path : step_files) {
    const json data = ParseJsonFile(path);
    const std::string file = path.string();
    const json& captures =
        AtPointer(file, "/captures", [&]() -> const json& { return data.at("captures"); });
    for (size_t c = 0; c < captures.size(); ++c) {
      const json& capture = captures[c];
      if (!HasType(capture, "RGBCamera")) continue;
      const std::string at = "/captures/" + std::to_string(c);
      std::vector<std::pair<uint32_t, uint32_t>> instances, boxes_3d, boxes_2d;
      CollectLabels(capture, at, "InstanceSegmentationAnnotation", "instances", file, &instances);
      CollectLabels(capture, at, "BoundingBox3DAnnotation", "values", file, &boxes_3d);
      CollectLabels(capture, at, "BoundingBox2DAnnotation", "values", file, &boxes_2d);
      for (const auto& [instance, label] : instances) use.used.insert(label);
      std::set<uint32_t> with_3d;
      for (const auto& [instance, label] : boxes_3d) {
        use.used.insert(label);
        with_3d.insert(instance);
      }
      for (const auto& [instance, label] : boxes_2d) {
        use.used.insert(label);
        if (with_3d.count(instance)) continue;
        const auto name = labels.find(label);
        ++use.boxes_2d_only[name == labels.end() ? "label " + std::to_string(label) : name->second];
      }
      break;
    }
  }
  return use;
}

// The classes: the labels the frames use (or all, --all-labels), so that no class of the
// table is empty only because the label configuration listed it.
void AddClasses(const std::map<uint32_t, std::string>& labels,
                const LabelUse& use,
                bool all_labels,
                SourceDescription* description) {
  for (const auto& [id, name] : labels)
    if (all_labels || use.used.count(id)) description->classes.push_back({id, name});
  for (const auto& [label, count] : use.boxes_2d_only)
    description->warnings.push_back(
        std::to_string(count) + " BoundingBox2D box(es) of '" + label +
        "' have no BoundingBox3D box: objects without a 3D box (no obb, no bbox_projected); "
        "their visibility and in_frame are the OcclusionMetric's where the frame has one, else "
        "not measured (1)");
}

// The layers, their origin and the source's conventions.
void DescribeTruth(bool has_depth, DepthKind depth_kind, SourceDescription* description) {
  description->semantics = {"rgb", "classid", "instanceid"};
  if (has_depth) description->semantics.push_back("depth");
  description->depth_kind = depth_kind;
  description->truth_origin = {{"rgb", "imported"},
                               {"instanceid", "imported"},
                               {"classid", "imported"},
                               {"camera", "imported"},
                               {"obb", "imported"}};
  if (has_depth) description->truth_origin["depth"] = "imported";
  description->source_conventions = {
      {"world_frame", "Unity world (left-handed, y up), to ENU (x, z, y)"},
      {"length_unit", "m"},
      {"camera_frame", "Unity camera: x right, y up, looks down +z"},
      {"quaternions", "serialized [x, y, z, w]"},
      {"intrinsics", "3x3 of Unity's OpenGL projection matrix, column-major"},
      {"converted_to", "ENU m, OpenCV camera, pixel-edge intrinsics"}};
}

}  // namespace

void SoloImporter::FindSteps(const fs::path& source) {
  static const std::regex sequence_name(R"(sequence\.(\d+))");
  static const std::regex step_name(R"(step(\d+)\.frame_data\.json)");
  for (const auto& folder : fs::directory_iterator(source)) {
    std::smatch m;
    const std::string name = folder.path().filename().string();
    if (!folder.is_directory() || !std::regex_match(name, m, sequence_name)) continue;
    const std::optional<int64_t> sequence =
        ParseInteger(m[1].str(), 0, std::numeric_limits<int64_t>::max());
    if (!sequence)
      throw Error("the sequence number is beyond 2^63 - 1", Location(folder.path().string()));
    for (const auto& file : fs::directory_iterator(folder.path())) {
      std::smatch s;
      const std::string file_name = file.path().filename().string();
      if (!std::regex_match(file_name, s, step_name)) continue;
      const std::optional<int64_t> step =
          ParseInteger(s[1].str(), 0, std::numeric_limits<int64_t>::max());
      if (!step) throw Error("the step number is beyond 2^63 - 1", Location(file.path().string()));
      steps_.push_back({*sequence, *step, root_->File(file.path())});
    }
  }
  if (steps_.empty()) throw Error("no sequence.N/stepK.frame_data.json", Location(source.string()));
  std::sort(steps_.begin(), steps_.end(), [](const Step& a, const Step& b) {
    return std::tie(a.sequence, a.step) < std::tie(b.sequence, b.step);
  });
  // Each sequence (one Scenario iteration) is one shot, starting at its first
  // frame.
  for (size_t k = 0; k < steps_.size(); ++k)
    shot_of_step_.push_back(k > 0 && steps_[k].sequence == steps_[k - 1].sequence
                                ? shot_of_step_[k - 1]
                                : static_cast<int64_t>(k));
}

// Whether there is depth, and of which kind: from the first frame.
void SoloImporter::FindDepth() {
  const json first = ParseJsonFile(steps_[0].file);
  const std::string first_file = steps_[0].file.string();
  AtPointer(first_file, "/captures", [&] {
    for (const json& capture : first.at("captures")) {
      if (!HasType(capture, "RGBCamera")) continue;
      for (const json& annotation : capture.value("annotations", json::array()))
        if (HasType(annotation, "DepthAnnotation")) {
          has_depth_ = true;
          depth_kind_ = annotation.value("measurementStrategy", "Depth") == "Range"
                            ? DepthKind::kPerspective
                            : DepthKind::kPlanar;
        }
      break;
    }
    return 0;
  });
}

SourceDescription SoloImporter::Open(const fs::path& source, const ImportOptions& options) {
  root_.emplace(source, options.allow_links_outside);
  const std::map<uint32_t, std::string> labels = ReadLabelDefinitions(*root_, source);
  for (const auto& [id, name] : labels) class_ids_.push_back(id);
  schedule_ = ReadCaptureSchedule(*root_, source);
  SourceDescription description;
  FindSteps(source);
  std::vector<fs::path> step_files;
  for (const Step& step : steps_) step_files.push_back(step.file);
  AddClasses(labels, ScanLabelUse(step_files, labels), options.all_labels, &description);
  FindDepth();
  description.frame_count = static_cast<int64_t>(steps_.size());
  DescribeTruth(has_depth_, depth_kind_, &description);
  return description;
}

namespace {

// The stages of SoloImporter::ReadFrame: the step's time and RGB capture, the capture's camera
// (pose and intrinsics), then each annotation of the capture by type: instance segmentation
// (the id layers), 3D bounding boxes (the targets) and depth.

// The RGB capture's pose in Unity's frame and its image size.
struct CaptureGeometry {
  Eigen::Vector3d position;
  Eigen::Matrix3d world_from_unity_cam;
  int width = 0, height = 0;
};

// The capture's camera: pose (to ENU and OpenCV's camera axes) and intrinsics.
CaptureGeometry ReadCaptureCamera(const json& capture,
                                  const std::string& file,
                                  const std::string& at,
                                  CameraTruth* camera_truth) {
  CaptureGeometry geometry;
  Eigen::Matrix<double, 4, 1> xyzw;
  Eigen::Matrix<double, 9, 1> matrix;
  int width = 0, height = 0;
  AtPointer(file, at + "/position", [&] {
    geometry.position = JsonNumbers<3>(capture.at("position"));
    return 0;
  });
  AtPointer(file, at + "/rotation", [&] {
    xyzw = JsonNumbers<4>(capture.at("rotation"));
    return 0;
  });
  AtPointer(file, at + "/matrix", [&] {
    matrix = JsonNumbers<9>(capture.at("matrix"));
    return 0;
  });
  AtPointer(file, at + "/dimension", [&] {
    const json& dimension = capture.at("dimension");
    width = IntegerAt<int>(dimension.at(0), file, at + "/dimension/0");
    height = IntegerAt<int>(dimension.at(1), file, at + "/dimension/1");
    return 0;
  });
  if (width < 1 || height < 1)
    throw Error("dimension must be positive", Location(file, at + "/dimension"));
  geometry.width = width;
  geometry.height = height;
  const Eigen::Matrix3d enu_from_unity = EnuFromUnity();
  geometry.world_from_unity_cam = RotationXyzw(xyzw, file, at + "/rotation");
  // The Unity camera's y is up, OpenCV's down; both look down +z.
  const Eigen::Matrix3d unity_cam_from_cv = Eigen::Vector3d(1, -1, 1).asDiagonal();
  const Eigen::Matrix3d world_from_cam =
      enu_from_unity * geometry.world_from_unity_cam * unity_cam_from_cv;
  camera_truth->cam_from_world_rotation = world_from_cam.transpose();
  camera_truth->cam_from_world_translation =
      -(world_from_cam.transpose() * (enu_from_unity * geometry.position));
  // Column-major 3x3 of the OpenGL projection: P00 at 0, P11 at 4, P02 at 6,
  // P12 at 7. x_ndc = P00 x / -z - P02 with u = (x_ndc + 1) W / 2 from the left
  // edge; y_ndc = P11 y / -z - P12 with v = (1 - y_ndc) H / 2 from the top.
  PinholeCamera& camera = camera_truth->intrinsics;
  camera.width = width, camera.height = height;
  camera.fx = 0.5 * width * matrix[0];
  camera.fy = 0.5 * height * matrix[4];
  camera.cx = 0.5 * width * (1 - matrix[6]);
  camera.cy = 0.5 * height * (1 + matrix[7]);
  if (!(camera.fx > 0 && camera.fy > 0))
    throw Error("not a perspective projection", Location(file, at + "/matrix"));
  return geometry;
}

// What an annotation reader needs of the step: its JSON file, frame index, image size and
// the files its annotations name (confined to the dataset).
struct StepContext {
  const std::string& file;
  int64_t index;
  int width, height;
  std::function<fs::path(const json& element, const std::string& where)> named_file;
};

// The instance and class id layers from the segmentation PNG's colours, which the
// annotation's instances map to ids.
void ReadInstanceSegmentation(const json& annotation,
                              const std::string& where,
                              const StepContext& step,
                              const std::vector<uint32_t>& class_ids,
                              SourceFrame* frame) {
  const std::string& file = step.file;
  const int width = step.width, height = step.height;
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> of_colour;  // rgba
  const json& instances = AtPointer(
      file, where + "/instances", [&]() -> const json& { return annotation.at("instances"); });
  for (size_t n = 0; n < instances.size(); ++n) {
    const std::string w = where + "/instances/" + std::to_string(n);
    uint32_t instance = 0, label = 0, rgba = 0;
    AtPointer(file, w, [&] {
      instance = IdAt(instances[n].at("instanceId"), file, w + "/instanceId");
      label = IdAt(instances[n].at("labelId"), file, w + "/labelId");
      const json& colour = instances[n].at("color");
      for (int ch = 0; ch < 4; ++ch)
        rgba = (rgba << 8) |
               IntegerAt<uint8_t>(colour.at(ch), file, w + "/color/" + std::to_string(ch));
      return 0;
    });
    if (instance == 0 || !std::binary_search(class_ids.begin(), class_ids.end(), label))
      throw Error(
          "instanceId must be >= 1 and labelId in "
          "annotation_definitions.json",
          Location(file, w));
    of_colour[rgba] = {instance, label};
  }
  const fs::path path = step.named_file(annotation, where);
  const cv::Mat colours = ReadRgbaPng(path, width, height);
  exr::FlatImage& ids = frame->flat["instanceid"] = exr::FlatImage(width, height);
  exr::FlatImage& classes = frame->flat["classid"] = exr::FlatImage(width, height);
  std::vector<uint32_t>& instance = ids.AddChannel("id", exr::PixelType::kUint).uints;
  std::vector<uint32_t>& klass = classes.AddChannel("id", exr::PixelType::kUint).uints;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const uint32_t rgba = PackedRgba(colours.at<cv::Vec4b>(j, i));
      const auto found = of_colour.find(rgba);
      if (found == of_colour.end()) {
        // Unlabelled surfaces and the sky are black.
        if ((rgba >> 8) == 0) continue;
        throw Error("colour " + RgbaText(rgba) + " is not in " + file + "#" + where + "/instances",
                    Location::Pixel(path.string(), step.index, i, j));
      }
      instance[ids.Index(i, j)] = found->second.first;
      klass[classes.Index(i, j)] = found->second.second;
    }
}

// The targets: each 3D bounding box, from the capture's camera frame to ENU.
void ReadBoundingBoxes3d(const json& annotation,
                         const std::string& where,
                         const std::string& file,
                         const CaptureGeometry& geometry,
                         SourceFrame* frame) {
  const Eigen::Matrix3d enu_from_unity = EnuFromUnity();
  const json& values =
      AtPointer(file, where + "/values", [&]() -> const json& { return annotation.at("values"); });
  for (size_t n = 0; n < values.size(); ++n) {
    const std::string w = where + "/values/" + std::to_string(n);
    ObjectIdentity target;
    Eigen::Vector3d translation, size;
    Eigen::Matrix<double, 4, 1> q;
    AtPointer(file, w, [&] {
      target.instance_id = IdAt(values[n].at("instanceId"), file, w + "/instanceId");
      target.class_id = IdAt(values[n].at("labelId"), file, w + "/labelId");
      target.name =
          values[n].value("labelName", std::string()) + "#" + std::to_string(target.instance_id);
      translation = JsonNumbers<3>(values[n].at("translation"));
      size = JsonNumbers<3>(values[n].at("size"));
      q = JsonNumbers<4>(values[n].at("rotation"));
      return 0;
    });
    if (!(size.minCoeff() >= 0)) throw Error("size must be >= 0", Location(file, w + "/size"));
    // In the camera's (Unity, left-handed) frame. Its axes, taken to ENU,
    // are a left-handed triple: negating the box's z keeps the same box.
    const Eigen::Matrix3d cam_from_box = RotationXyzw(q, file, w + "/rotation");
    OrientedBox& obb = target.obb.emplace();
    obb.center = enu_from_unity * (geometry.world_from_unity_cam * translation + geometry.position);
    obb.half_extents = 0.5 * size;
    obb.world_from_box = enu_from_unity * geometry.world_from_unity_cam * cam_from_box *
                         Eigen::Vector3d(1, 1, -1).asDiagonal();
    frame->targets.push_back(target);
  }
}

// The objects with a 2D box and no 3D box (BoundingBox2DAnnotation's values whose instance no
// BoundingBox3DAnnotation value has): targets without an OBB, measured on the instance mask.
void ReadBoxes2dOnly(const json& annotation,
                     const std::string& where,
                     const std::string& file,
                     const std::vector<uint32_t>& class_ids,
                     SourceFrame* frame) {
  std::set<uint32_t> with_obb;
  for (const ObjectIdentity& target : frame->targets) with_obb.insert(target.instance_id);
  const json& values =
      AtPointer(file, where + "/values", [&]() -> const json& { return annotation.at("values"); });
  for (size_t n = 0; n < values.size(); ++n) {
    const std::string w = where + "/values/" + std::to_string(n);
    ObjectIdentity target;
    AtPointer(file, w, [&] {
      target.instance_id = IdAt(values[n].at("instanceId"), file, w + "/instanceId");
      target.class_id = IdAt(values[n].at("labelId"), file, w + "/labelId");
      target.name =
          values[n].value("labelName", std::string()) + "#" + std::to_string(target.instance_id);
      return 0;
    });
    if (!std::binary_search(class_ids.begin(), class_ids.end(), target.class_id))
      throw Error("labelId is not in annotation_definitions.json", Location(file, w + "/labelId"));
    if (with_obb.insert(target.instance_id).second) frame->targets.push_back(target);
  }
}

// The OcclusionLabeler's metric (Perception 1.0, OcclusionLabeler.cs ReportOcclusionMetrics):
// visibilityInFrame is visible / unoccluded pixels inside the image, lsds's visibility, and
// percentInFrame the share of the object's unoccluded pixels inside the image, its in_frame.
void ReadOcclusionMetric(const json& data, const std::string& file, SourceFrame* frame) {
  const json metrics = data.value("metrics", json::array());
  for (size_t m = 0; m < metrics.size(); ++m) {
    if (!HasType(metrics[m], "OcclusionMetric")) continue;
    const std::string where = "/metrics/" + std::to_string(m) + "/values";
    const json& values =
        AtPointer(file, where, [&]() -> const json& { return metrics[m].at("values"); });
    for (size_t n = 0; n < values.size(); ++n) {
      const std::string w = where + "/" + std::to_string(n);
      AtPointer(file, w, [&] {
        const uint32_t instance = IdAt(values[n].at("instanceId"), file, w + "/instanceId");
        const double visible = values[n].at("visibilityInFrame").get<double>();
        const double in_frame = values[n].at("percentInFrame").get<double>();
        if (!(visible >= 0 && visible <= 1 && in_frame >= 0 && in_frame <= 1))
          throw Error("visibilityInFrame and percentInFrame must be in [0, 1]", Location(file, w));
        frame->stated[instance].visibility = visible;
        frame->stated[instance].in_frame = in_frame;
        return 0;
      });
    }
  }
}

// The depth layer from the annotation's EXR: 0 (nothing rendered) is sky.
void ReadDepthAnnotation(const json& annotation,
                         const std::string& where,
                         const StepContext& step,
                         SourceFrame* frame) {
  const int width = step.width, height = step.height;
  const fs::path path = step.named_file(annotation, where);
  const exr::FlatImage depth_exr = exr::ReadFlatExr(path, {"R"});
  if (depth_exr.width() != width || depth_exr.height() != height)
    throw Error("not " + std::to_string(width) + "x" + std::to_string(height),
                Location(path.string()));
  exr::FlatImage& depth = frame->flat["depth"] = exr::FlatImage(width, height);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  const std::vector<float>& r = depth_exr.Get("R").floats;
  for (size_t p = 0; p < z.size(); ++p) {
    // NaN is no surface anyone rendered: an error, not sky.
    if (r[p] < 0 || std::isnan(r[p]))
      throw Error(
          std::isnan(r[p]) ? "NaN depth" : "negative depth",
          Location::Pixel(
              path.string(), step.index, static_cast<int>(p % width), static_cast<int>(p / width)));
    // 0 where nothing was rendered (the sky).
    z[p] = r[p] > 0 && std::isfinite(r[p]) ? r[p] : std::numeric_limits<float>::infinity();
  }
}

}  // namespace

SourceFrame SoloImporter::ReadFrame(int64_t index) {
  const Step& step = steps_.at(static_cast<size_t>(index));
  const std::string file = step.file.string();
  const fs::path folder = step.file.parent_path();
  const json data = ParseJsonFile(step.file);
  SourceFrame frame;
  frame.sequence = "sequence." + std::to_string(step.sequence);
  frame.shot = shot_of_step_.at(static_cast<size_t>(index));
  // Seconds since the sequence started: Frame.ToMessage writes SimulationState.SequenceTime,
  // a sum of Unity's Time.deltaTime (seconds), whatever the schema page says (milliseconds).
  // Frames before Perception 1.0 have no timestamp: the sensor's schedule gives the time.
  frame.time =
      data.contains("timestamp")
          ? AtPointer(file, "/timestamp", [&] { return data.at("timestamp").get<double>(); })
          : schedule_.TimeOfStep(step.step);
  size_t c = 0;
  const json& captures =
      AtPointer(file, "/captures", [&]() -> const json& { return data.at("captures"); });
  while (c < captures.size() && !HasType(captures[c], "RGBCamera")) ++c;
  if (c == captures.size()) throw Error("no RGBCamera capture", Location(file, "/captures"));
  const json& capture = captures[c];
  const std::string at = "/captures/" + std::to_string(c);
  const CaptureGeometry geometry = ReadCaptureCamera(capture, file, at, &frame.camera);

  // Names in the capture are relative to the step's folder and confined to
  // the dataset.
  const StepContext context{
      file,
      index,
      geometry.width,
      geometry.height,
      [&](const json& element, const std::string& where) {
        const std::string pointer = where + "/filename";
        const json& name =
            AtPointer(file, pointer, [&]() -> const json& { return element.at("filename"); });
        return root_->Reference(folder, StringAt(name, file, pointer), Location(file, pointer));
      }};
  frame.flat["rgb"] = ReadSrgbLayer(
      context.named_file(capture, at), geometry.width, geometry.height, "the capture's dimension");

  bool have_instances = false;
  const json annotations = capture.value("annotations", json::array());
  std::optional<size_t> boxes_2d;
  for (size_t a = 0; a < annotations.size(); ++a) {
    const json& annotation = annotations[a];
    const std::string where = at + "/annotations/" + std::to_string(a);
    if (HasType(annotation, "InstanceSegmentationAnnotation")) {
      have_instances = true;
      ReadInstanceSegmentation(annotation, where, context, class_ids_, &frame);
    } else if (HasType(annotation, "BoundingBox3DAnnotation")) {
      ReadBoundingBoxes3d(annotation, where, file, geometry, &frame);
    } else if (HasType(annotation, "BoundingBox2DAnnotation")) {
      boxes_2d = a;  // read once the 3D boxes are known
    } else if (HasType(annotation, "DepthAnnotation") && has_depth_) {
      ReadDepthAnnotation(annotation, where, context, &frame);
    }
  }
  if (!have_instances)
    throw Error("no InstanceSegmentationAnnotation in the RGB capture",
                Location(file, at + "/annotations"));
  if (boxes_2d)
    ReadBoxes2dOnly(annotations[*boxes_2d],
                    at + "/annotations/" + std::to_string(*boxes_2d),
                    file,
                    class_ids_,
                    &frame);
  ReadOcclusionMetric(data, file, &frame);
  if (has_depth_ && !frame.flat.count("depth"))
    throw Error("no DepthAnnotation (the first frame has one)",
                Location(file, at + "/annotations"));
  return frame;
}

}  // namespace lsds::import
