#include "evaluate/ground_truth.h"

#include <stdlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <sstream>
#include <system_error>

#include "converters/convert.h"
#include "evaluate/segmentation.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/model.h"
#include "libs/collection/requirement_summary.h"
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

// A number of the record, NaN when absent.
double NumberOr(const json& object, const char* key) {
  if (!object.is_object()) return FrameFacts::kNone;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return FrameFacts::kNone;
  return it->get<double>();
}

// A label of the record, interned; null when absent.
const std::string* LabelOr(const json& object, const char* key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_string()) return nullptr;
  return InternLabel(it->get_ref<const std::string&>());
}

// What a frame record says about its conditions (docs/format.md, "Scene
// state"); the camera's optical axis in ENU gives the off-nadir angle.
FrameFacts FactsOf(const Frame& frame, const WorldFrame& world) {
  FrameFacts facts;
  const Eigen::Vector3d axis_in_world = frame.camera.cam_from_world_rotation.row(2).transpose();
  const Eigen::Vector3d axis = (world.enu_from_frame * axis_in_world).normalized();
  facts.off_nadir_deg = std::acos(std::clamp(-axis.z(), -1.0, 1.0)) * 180.0 / M_PI;
  const Eigen::Matrix3d& r = frame.camera.cam_from_world_rotation;
  const Eigen::Vector3d centre = -(r.transpose() * frame.camera.cam_from_world_translation);
  facts.camera_in_world = {centre.x(), centre.y(), centre.z()};
  const json& scene = frame.scene;
  if (!scene.is_object()) return facts;
  if (scene.contains("sun")) facts.sun_elevation_deg = NumberOr(scene["sun"], "elevation_deg");
  if (scene.contains("atmosphere")) {
    facts.atmosphere_recorded = true;
    facts.fog_visibility_m = NumberOr(scene["atmosphere"], "visibility_m");
  }
  if (scene.contains("sky")) {
    const json& sky = scene["sky"];
    facts.clouds = LabelOr(sky, "cloud_type");
    if (NumberOr(sky, "cloud_density") <= 0) facts.clouds = InternLabel("none");
  }
  facts.terrain_material = LabelOr(scene, "terrain_material");
  return facts;
}

// The bin each quota's check of a frame record achieved (requirement_summary.h
// counts the same), -1 for none.
std::vector<int16_t> AchievedQuotaBins(const json& quotas, const json& record) {
  std::vector<int16_t> bins(quotas.size(), -1);
  if (!record.is_object() || !record.contains("checks")) return bins;
  for (size_t q = 0; q < quotas.size(); ++q) {
    const std::string& name = quotas[q].at("name").get_ref<const std::string&>();
    for (const json& check : record.at("checks")) {
      if (check.value("name", "") != name) continue;
      if (check.contains("achieved")) {
        const size_t bin = QuotaBinOf(quotas[q], check.at("achieved").get<double>());
        if (bin < quotas[q].at("weights").size()) bins[q] = static_cast<int16_t>(bin);
      }
      break;  // one check per quota and frame
    }
  }
  return bins;
}

// The frames' conditions, and where their cameras are.
void ReadFrameFacts(const TruthOptions& options, EvaluationTruth* truth) {
  const CollectionReader reader(options.collection);
  const WorldFrame& world = reader.header().conventions.world;
  truth->capture_source = reader.header().provenance.capture_source;
  truth->metres_per_unit = world.metres_per_unit;
  const json& requirements = reader.header().provenance.requirements;
  if (requirements.is_object() && requirements.contains("quotas"))
    truth->quotas = requirements.at("quotas");
  reader.ForEachFrame([&](const Frame& frame) {
    if (!options.frames.Contains(frame.index)) return;
    FrameFacts facts = FactsOf(frame, world);
    facts.index = frame.index;
    facts.quota_bins = AchievedQuotaBins(truth->quotas, frame.requirements);
    truth->frames.Add(std::move(facts));
  });
  truth->frames.Seal();
  const fs::path metadata = options.collection / kMetadataFile;
  if (!fs::exists(metadata)) return;
  MetadataReader(metadata).ForEachFrame([&](const MetadataFrame& frame) {
    FrameFacts* facts = truth->frames.Find(frame.index);
    if (facts == nullptr) return;
    facts->altitude_agl_m = frame.altitude_agl_m.value_or(FrameFacts::kNone);
    facts->gsd_m = frame.gsd_m.value_or(FrameFacts::kNone);
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
  convert.mot_classes = options.mot_classes;
  convert.progress = false;
  return convert;
}

}  // namespace

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

namespace {

void ReadImageEntry(const json& image, EvaluationTruth* truth) {
  const int64_t id = image.at("id").get<int64_t>();
  truth->coco.image_ids.push_back(id);
  truth->images.Add(id,
                    image.at("file_name").get_ref<const std::string&>(),
                    image.at("lsds").at("frame").get<int64_t>(),
                    image.at("height").get<int64_t>(),
                    image.at("width").get<int64_t>());
}

void ReadCategories(const json& coco, const std::string& file, EvaluationTruth* truth) {
  AtPointer(file, "/categories", [&] {
    for (const json& category : coco.at("categories")) {
      truth->coco.category_ids.push_back(category.at("id").get<int64_t>());
      truth->category_names.push_back(category.at("name").get<std::string>());
    }
  });
}

// One annotation and the facts of its object; its distance from the camera
// of its frame (when both are known).
void ReadAnnotationEntry(const json& a,
                         const std::string& file,
                         const std::string& at,
                         const EvaluationTruth& truth,
                         bool masks,
                         TruthImage* image) {
  AtPointer(file, at, [&] {
    GroundTruthBox g;
    g.id = a.at("id").get<int64_t>();
    g.image_id = a.at("image_id").get<int64_t>();
    g.category_id = a.at("category_id").get<int64_t>();
    g.bbox = ReadBox(a.at("bbox"));
    g.area = a.at("area").get<double>();
    g.iscrowd = a.at("iscrowd").get<int>() != 0;
    g.ignored = truth.ignored_categories.count(g.category_id) > 0;
    if (masks) {
      const EvaluationTruth::ImageSize size = truth.SizeOf(g.image_id);
      g.mask = ReadSegmentation(
          a.at("segmentation"), size.height, size.width, file, at + "/segmentation");
    }
    ObjectFacts facts;
    facts.frame = truth.images.At(g.image_id).frame;
    facts.size_px = std::max(g.bbox.w, g.bbox.h);
    if (const auto lsds = a.find("lsds"); lsds != a.end()) {
      facts.instance_id = lsds->at("instance_id").get<uint32_t>();
      facts.name = lsds->value("name", "");
      facts.visibility = lsds->at("visibility").get<double>();
      facts.in_frame = lsds->at("in_frame").get<double>();
      const FrameFacts* frame = truth.frames.Find(facts.frame);
      if (const auto obb = lsds->find("obb");
          obb != lsds->end() && frame != nullptr && frame->camera_known()) {
        const json& c = obb->at("center");
        const Eigen::Vector3d center(
            c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>());
        const std::array<double, 3>& camera = frame->camera_in_world;
        const Eigen::Vector3d centre(camera[0], camera[1], camera[2]);
        facts.distance_m = truth.metres_per_unit * (center - centre).norm();
      }
    }
    image->boxes.push_back(std::move(g));
    image->objects.push_back(std::move(facts));
  });
}

void SortImageIds(EvaluationTruth* truth) {
  std::vector<int64_t>& ids = truth->coco.image_ids;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

}  // namespace

struct StreamedAnnotations {
  fs::path file;
  bool masks = false;
  std::shared_ptr<void> keep_alive;
};

void EvaluationTruth::ForEachImage(const std::function<void(TruthImage&&)>& on_image) const {
  std::vector<int64_t> ids = coco.image_ids;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  size_t next = 0;  // the next image to hand out
  const auto empty_until = [&](int64_t id) {
    for (; next < ids.size() && ids[next] < id; ++next) {
      TruthImage empty;
      empty.image_id = ids[next];
      on_image(std::move(empty));
    }
  };
  if (!streamed) {
    std::map<int64_t, std::vector<size_t>> by_image;
    for (size_t i = 0; i < coco.ground_truth.size(); ++i)
      by_image[coco.ground_truth[i].image_id].push_back(i);
    for (const auto& [id, indices] : by_image) {
      empty_until(id);
      if (next == ids.size() || ids[next] != id) continue;  // not an image of the truth
      TruthImage image;
      image.image_id = id;
      ++next;
      for (size_t i : indices) {
        image.boxes.push_back(coco.ground_truth[i]);
        if (ignored_categories.count(image.boxes.back().category_id))
          image.boxes.back().ignored = true;
        image.objects.push_back(i < objects.size() ? objects[i] : ObjectFacts{});
      }
      on_image(std::move(image));
    }
    empty_until(std::numeric_limits<int64_t>::max());
    return;
  }
  const std::string file = streamed->file.string();
  TruthImage current;
  bool open = false;
  StreamJsonArrays(streamed->file,
                   {"images", "annotations"},
                   nullptr,
                   [&](const std::string& key, json&& element, size_t index) {
                     if (key != "annotations") return;
                     const std::string at = "/annotations/" + std::to_string(index);
                     TruthImage one;
                     ReadAnnotationEntry(element, file, at, *this, streamed->masks, &one);
                     const int64_t id = one.boxes.front().image_id;
                     if (open && id == current.image_id) {
                       current.boxes.push_back(std::move(one.boxes.front()));
                       current.objects.push_back(std::move(one.objects.front()));
                       return;
                     }
                     if (open && id < current.image_id)
                       throw Error(
                           "the annotations are not grouped by image in id order, as lsds convert "
                           "writes them",
                           Location(file, at + "/image_id"));
                     if (open) on_image(std::move(current));
                     open = false;
                     empty_until(id);
                     if (next == ids.size() || ids[next] != id)
                       throw Error("image " + std::to_string(id) + " is not in /images",
                                   Location(file, at + "/image_id"));
                     current = std::move(one);
                     current.image_id = id;
                     ++next;
                     open = true;
                   });
  if (open) on_image(std::move(current));
  empty_until(std::numeric_limits<int64_t>::max());
}

void HoldAnnotations(EvaluationTruth* truth) {
  if (!truth->streamed) return;
  std::vector<GroundTruthBox> boxes;
  std::vector<ObjectFacts> objects;
  truth->ForEachImage([&](TruthImage&& image) {
    std::move(image.boxes.begin(), image.boxes.end(), std::back_inserter(boxes));
    std::move(image.objects.begin(), image.objects.end(), std::back_inserter(objects));
  });
  truth->coco.ground_truth = std::move(boxes);
  truth->objects = std::move(objects);
  truth->streamed.reset();
  truth->streamed_annotations = 0;
}

EvaluationTruth StreamCocoGroundTruth(const fs::path& file,
                                      bool masks,
                                      std::shared_ptr<void> keep_alive) {
  EvaluationTruth truth;
  if (masks) truth.coco.iou_type = IouType::kMask;
  json header;
  const std::string name = file.string();
  StreamJsonArrays(file,
                   {"images", "annotations"},
                   &header,
                   [&](const std::string& key, json&& element, size_t index) {
                     if (key == "annotations") {
                       ++truth.streamed_annotations;
                       return;
                     }
                     AtPointer(name, "/images/" + std::to_string(index), [&] {
                       ReadImageEntry(element, &truth);
                     });
                   });
  ReadCategories(header, name, &truth);
  SortImageIds(&truth);
  truth.images.Seal();
  auto streamed = std::make_shared<StreamedAnnotations>();
  streamed->file = file;
  streamed->masks = masks;
  streamed->keep_alive = std::move(keep_alive);
  truth.streamed = std::move(streamed);
  return truth;
}

EvaluationTruth StreamCollectionTruth(const TruthOptions& options) {
  return StreamCollectionTruth(options, {});
}

EvaluationTruth StreamCollectionTruth(const TruthOptions& options,
                                      std::vector<std::unique_ptr<convert::Converter>> also) {
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
  // The converter, run as `lsds convert COLLECTION --to coco --images none`;
  // its file is read again image by image while the truth lives.
  auto scratch = std::make_shared<ScratchFolder>();
  const convert::ConvertOptions coco = ConverterOptions(options, "coco", scratch->path());
  convert::Convert(coco, std::move(also));
  const fs::path file = coco.output / "annotations" / "instances_train.json";
  EvaluationTruth truth = StreamCocoGroundTruth(file, options.masks, scratch);
  ReadFrameFacts(options, &truth);
  return truth;
}

EvaluationTruth ReadCollectionTruth(const TruthOptions& options) {
  EvaluationTruth truth = StreamCollectionTruth(options);
  HoldAnnotations(&truth);
  return truth;
}

}  // namespace lsds::evaluate
