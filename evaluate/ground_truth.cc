#include "evaluate/ground_truth.h"

#include <stdlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <system_error>

#include "converters/convert.h"
#include "evaluate/dota_files.h"
#include "evaluate/segmentation.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/model.h"
#include "libs/geometry/world_frame.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"

namespace lsds::evaluate {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A private scratch folder under the system's temporary folder, removed with
// everything in it when the object goes.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::string pattern = (fs::temp_directory_path() / "lsds-evaluate-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw Error("cannot make a scratch folder", Location(pattern));
    path_ = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

BoxXywh ReadBox(const json& box) {
  return {box.at(0).get<double>(),
          box.at(1).get<double>(),
          box.at(2).get<double>(),
          box.at(3).get<double>()};
}

std::optional<double> OptionalNumber(const json& object, const char* key) {
  if (!object.is_object()) return std::nullopt;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

std::optional<std::string> OptionalString(const json& object, const char* key) {
  if (!object.is_object()) return std::nullopt;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_string()) return std::nullopt;
  return it->get<std::string>();
}

// What a frame record says about its conditions (docs/format.md, "Scene
// state"); the camera's optical axis in ENU gives the off-nadir angle.
FrameFacts FactsOf(const Frame& frame, const WorldFrame& world) {
  FrameFacts facts;
  const Eigen::Vector3d axis_in_world = frame.camera.cam_from_world_rotation.row(2).transpose();
  const Eigen::Vector3d axis = (world.enu_from_frame * axis_in_world).normalized();
  facts.off_nadir_deg = std::acos(std::clamp(-axis.z(), -1.0, 1.0)) * 180.0 / M_PI;
  const json& scene = frame.scene;
  if (!scene.is_object()) return facts;
  if (scene.contains("sun"))
    facts.sun_elevation_deg = OptionalNumber(scene["sun"], "elevation_deg");
  if (scene.contains("atmosphere")) {
    facts.atmosphere_recorded = true;
    facts.fog_visibility_m = OptionalNumber(scene["atmosphere"], "visibility_m");
  }
  if (scene.contains("sky")) {
    const json& sky = scene["sky"];
    facts.clouds = OptionalString(sky, "cloud_type");
    if (OptionalNumber(sky, "cloud_density").value_or(1.0) <= 0) facts.clouds = "none";
  }
  facts.terrain_material = OptionalString(scene, "terrain_material");
  return facts;
}

// The frames' conditions and every object's distance, keyed by frame and
// instance id.
void ReadFrameFacts(const TruthOptions& options,
                    EvaluationTruth* truth,
                    std::map<std::pair<int64_t, uint32_t>, double>* distances) {
  const CollectionReader reader(options.collection);
  const WorldFrame& world = reader.header().conventions.world;
  truth->capture_source = reader.header().provenance.capture_source;
  reader.ForEachFrame([&](const Frame& frame) {
    if (!options.frames.Contains(frame.index)) return;
    truth->frames[frame.index] = FactsOf(frame, world);
    const Eigen::Matrix3d& r = frame.camera.cam_from_world_rotation;
    const Eigen::Vector3d centre = -(r.transpose() * frame.camera.cam_from_world_translation);
    for (const ObjectTruth& object : frame.objects) {
      if (!object.obb) continue;  // no 3D box: no distance (its bins say "unknown")
      (*distances)[{frame.index, object.instance_id}] =
          world.metres_per_unit * (object.obb->center - centre).norm();
    }
  });
  const fs::path metadata = options.collection / kMetadataFile;
  if (!fs::exists(metadata)) return;
  MetadataReader(metadata).ForEachFrame([&](const MetadataFrame& frame) {
    const auto it = truth->frames.find(frame.index);
    if (it == truth->frames.end()) return;
    it->second.altitude_agl_m = frame.altitude_agl_m;
    it->second.gsd_m = frame.gsd_m;
  });
}

// `lsds convert COLLECTION --to FORMAT --images none` with the flags of
// `options`, into `scratch`.
convert::ConvertOptions ConverterOptions(const TruthOptions& options,
                                         const std::string& format,
                                         const fs::path& scratch) {
  convert::ConvertOptions convert;
  convert.collection = options.collection;
  convert.output = scratch / format;
  convert.formats = {format};
  convert.images = "none";
  convert.frames = options.frames;
  convert.classes = options.classes;
  convert.keep_classes = options.keep_classes;
  convert.min_visibility = options.min_visibility;
  convert.min_pixels = options.min_pixels;
  convert.progress = false;
  return convert;
}

}  // namespace

DotaTruth ReadDotaTruth(const TruthOptions& options) {
  const ScratchFolder scratch;
  const convert::ConvertOptions dota = ConverterOptions(options, "dota", scratch.path());
  convert::Convert(dota);
  DotaTruth truth;
  std::istringstream classes(ReadTextFile(dota.output / "dota_classes.txt"));
  for (std::string name; std::getline(classes, name);)
    if (!name.empty()) truth.class_names.push_back(name);
  std::vector<fs::path> labels;
  for (const auto& entry : fs::recursive_directory_iterator(dota.output / "labelTxt"))
    if (entry.path().extension() == ".txt") labels.push_back(entry.path());
  std::sort(labels.begin(), labels.end());
  for (const fs::path& label : labels) {
    const std::string image = label.stem().string();
    truth.images.insert(image);
    for (DotaObject& o : ParseDotaLabels(ReadTextFile(label), label.string(), image))
      truth.objects.push_back(std::move(o));
  }
  return truth;
}

MotSequences ReadMotSequences(const TruthOptions& options) {
  const ScratchFolder scratch;
  const convert::ConvertOptions mot = ConverterOptions(options, "mot", scratch.path());
  convert::Convert(mot);
  MotSequences sequences;
  for (const auto& entry : fs::recursive_directory_iterator(mot.output / "mot")) {
    if (entry.path().filename() != "frames.txt") continue;
    std::vector<int64_t>& frames = sequences[entry.path().parent_path().filename().string()];
    std::istringstream in(ReadTextFile(entry.path()));
    for (std::string line; std::getline(in, line);) {
      // "number,collection_frame" after the header line, numbers from 1 in order.
      const size_t comma = line.find(',');
      if (comma == std::string::npos || line.empty() || !std::isdigit(line[0])) continue;
      frames.push_back(std::strtoll(line.c_str() + comma + 1, nullptr, 10));
    }
  }
  return sequences;
}

void ReadCocoGroundTruth(const json& coco,
                         const std::string& file,
                         EvaluationTruth* truth,
                         bool masks) {
  if (masks) truth->coco.iou_type = IouType::kMask;
  AtPointer(file, "/images", [&] {
    for (const json& image : coco.at("images")) {
      const int64_t id = image.at("id").get<int64_t>();
      truth->coco.image_ids.push_back(id);
      truth->image_by_file_name[image.at("file_name").get<std::string>()] = id;
      truth->frame_of_image[id] = image.at("lsds").at("frame").get<int64_t>();
      truth->image_size[id] = {image.at("height").get<int64_t>(), image.at("width").get<int64_t>()};
    }
  });
  AtPointer(file, "/categories", [&] {
    for (const json& category : coco.at("categories")) {
      truth->coco.category_ids.push_back(category.at("id").get<int64_t>());
      truth->category_names.push_back(category.at("name").get<std::string>());
    }
  });
  AtPointer(file, "/annotations", [&] {
    const json& annotations = coco.at("annotations");
    for (size_t i = 0; i < annotations.size(); ++i) {
      const json& a = annotations[i];
      GroundTruthBox g;
      g.id = a.at("id").get<int64_t>();
      g.image_id = a.at("image_id").get<int64_t>();
      g.category_id = a.at("category_id").get<int64_t>();
      g.bbox = ReadBox(a.at("bbox"));
      g.area = a.at("area").get<double>();
      g.iscrowd = a.at("iscrowd").get<int>() != 0;
      if (masks) {
        const EvaluationTruth::ImageSize size = truth->image_size.at(g.image_id);
        g.mask = ReadSegmentation(a.at("segmentation"),
                                  size.height,
                                  size.width,
                                  file,
                                  "/annotations/" + std::to_string(i) + "/segmentation");
      }
      truth->coco.ground_truth.push_back(g);
      ObjectFacts facts;
      facts.frame = truth->frame_of_image.at(g.image_id);
      facts.size_px = std::max(g.bbox.w, g.bbox.h);
      if (const auto lsds = a.find("lsds"); lsds != a.end()) {
        facts.instance_id = lsds->at("instance_id").get<uint32_t>();
        facts.name = lsds->value("name", "");
        facts.visibility = lsds->at("visibility").get<double>();
        facts.in_frame = lsds->at("in_frame").get<double>();
      }
      truth->objects.push_back(facts);
    }
  });
}

EvaluationTruth ReadCollectionTruth(const TruthOptions& options) {
  {
    // The ground truth boxes and masks come from the instance layer; a
    // collection imported from a source without ids has none
    // (docs/import.md, "Import what is there").
    const CollectionReader reader(options.collection);
    if (reader.header().FindLayerBySemantic("instanceid") == nullptr)
      throw Error(
          "the collection has no instanceid layer, so no objects to evaluate detections against",
          Location(reader.collection_path().string(), "/layers"));
  }
  // The converter, run as `lsds convert COLLECTION --to coco --images none`.
  const ScratchFolder scratch;
  const convert::ConvertOptions coco = ConverterOptions(options, "coco", scratch.path());
  convert::Convert(coco);
  const fs::path file = coco.output / "annotations" / "instances_train.json";
  EvaluationTruth truth;
  ReadCocoGroundTruth(ReadJsonFile(file), file.string(), &truth, options.masks);

  std::map<std::pair<int64_t, uint32_t>, double> distances;
  ReadFrameFacts(options, &truth, &distances);
  for (ObjectFacts& object : truth.objects) {
    const auto it = distances.find({object.frame, object.instance_id});
    if (it != distances.end()) object.distance_m = it->second;
  }
  return truth;
}

}  // namespace lsds::evaluate
