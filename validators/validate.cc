#include "validators/validate.h"

#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <unordered_set>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "libs/collection/collection_reader.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/schema.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"
#include "validators/frame_checks.h"
#include "validators/truth_origin_check.h"

namespace lsds::validate {

namespace fs = std::filesystem;

namespace {

class Validator {
 public:
  Validator(const fs::path& root, const ValidateOptions& options)
      : root_(root), options_(options), report_(options.max_examples) {}

  Report Run();

 private:
  bool Selected(const std::string& id) const { return options_.checks.Has(id); }
  void Emit(const std::string& id,
            Location location,
            const std::string& message,
            const std::string& object = "") {
    if (!Selected(id)) return;
    report_.Add(
        {GetCheck(id).severity, id, std::move(location), object, message});
  }
  static Location Json(const std::string& file,
                       const std::string& pointer,
                       std::optional<int64_t> frame = std::nullopt) {
    Location where(file, pointer.empty() ? "/" : pointer);
    where.frame = frame;
    return where;
  }

  bool ReadHeader();
  void CheckTables();
  void ReadMetadata();
  void StreamFrames();
  void CheckFrameStructure(const Frame& frame, size_t position);
  void FlushBatch();
  void CheckStrayFiles();
  void CheckStatistics();

  fs::path root_;
  ValidateOptions options_;
  Report report_;
  CollectionHeader header_;
  size_t frames_in_file_ = 0;

  // Streaming state: O(1) per frame except the hashes of referenced files (8
  // bytes per file) and the compact metadata poses (one per frame), both
  // documented in docs/validate.md.
  std::vector<FrameInput> batch_;
  std::optional<Frame> previous_;
  std::unordered_set<uint64_t> referenced_;
  std::set<std::string> layer_folders_;
  struct MetadataPose {
    Eigen::Vector3d position;
    Attitude attitude;
  };
  struct MetadataFile {
    std::string file;
    bool perturbed = false;
    std::map<int64_t, MetadataPose> poses;
    Statistic position_error, angle_error;
    int64_t mismatched = 0;
    std::optional<int64_t> first_mismatch;
  };
  std::vector<MetadataFile> metadata_;
  std::map<uint32_t, int64_t> objects_per_class_;
  std::set<uint32_t> pixel_classes_;
  std::mutex tally_mutex_;
};

bool Validator::ReadHeader() {
  nlohmann::json header_json;
  // Syntax errors throw lsds::Error with line:column: the input cannot be read
  // as a collection.
  frames_in_file_ = StreamJsonArrayMember(
      root_ / kCollectionFile, "frames", &header_json, nullptr);
  const std::vector<SchemaIssue> issues =
      JsonSchema::Get("collection.schema.json").Validate(header_json);
  for (const SchemaIssue& issue : issues) {
    Emit("schema", Json(kCollectionFile, issue.pointer), issue.message);
  }
  try {
    header_ = HeaderFromJson(header_json, kCollectionFile);
  } catch (const Error& e) {
    // Past its schema, what the header parser refuses is a table inconsistency
    // (a duplicate class id or layer name, handedness against the world frame):
    // the frames cannot be checked then.
    if (issues.empty()) {
      Emit("structure.tables",
           Json(kCollectionFile, e.location().json_pointer),
           e.message() + " (the frames were not checked)");
    }
    return false;
  } catch (const std::exception& e) {
    // Only reachable past schema violations, which are reported already.
    if (issues.empty()) {
      Emit("schema",
           Json(kCollectionFile, "/"),
           std::string("header cannot be read: ") + e.what());
    }
    return false;
  }
  return true;
}

void Validator::CheckTables() {
  std::set<uint32_t> class_ids;
  for (size_t k = 0; k < header_.classes.size(); ++k) {
    if (!class_ids.insert(header_.classes[k].id).second) {
      Emit("structure.tables",
           Json(kCollectionFile, "/classes/" + std::to_string(k) + "/id"),
           "class id " + std::to_string(header_.classes[k].id) +
               " appears twice in the class table");
    }
  }
  std::set<std::string> names;
  for (size_t k = 0; k < header_.layers.size(); ++k) {
    const LayerInfo& layer = header_.layers[k];
    const std::string pointer = "/layers/" + std::to_string(k);
    if (!names.insert(layer.name).second) {
      Emit("structure.tables",
           Json(kCollectionFile, pointer + "/name"),
           "layer name '" + layer.name + "' appears twice in the layer table");
    }
    if ((layer.semantic == "depth" || layer.semantic == "bundle") &&
        !layer.depth_kind) {
      Emit("structure.tables",
           Json(kCollectionFile, pointer),
           "layer '" + layer.name + "' holds depth but declares no depth_kind");
    }
    if (layer.semantic == "bundle" && !layer.deep) {
      Emit("structure.tables",
           Json(kCollectionFile, pointer + "/deep"),
           "bundle layer '" + layer.name + "' must be deep");
    }
  }
  if (static_cast<size_t>(header_.frame_count) != frames_in_file_) {
    Emit("structure.frame-count",
         Json(kCollectionFile, "/frame_count"),
         "frame_count is " + std::to_string(header_.frame_count) +
             " but the file has " + std::to_string(frames_in_file_) +
             " frames");
  }
}

void Validator::ReadMetadata() {
  for (size_t k = 0; k < header_.metadata.size(); ++k) {
    const MetadataVariant& variant = header_.metadata[k];
    const fs::path path = root_ / variant.file;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      Emit("structure.metadata",
           Json(kCollectionFile, "/metadata/" + std::to_string(k) + "/file"),
           "metadata file '" + variant.file + "' does not exist");
      continue;
    }
    MetadataFile file;
    file.file = variant.file;
    file.perturbed = variant.perturbed;
    try {
      nlohmann::json header_json;
      const JsonSchema& frame_schema =
          JsonSchema::Get("metadata.schema.json", "frame");
      const size_t frames = StreamJsonArrayMember(
          path,
          "frames",
          &header_json,
          [&](nlohmann::json&& json, size_t index) {
            const std::string pointer = "/frames/" + std::to_string(index);
            const auto issues = frame_schema.Validate(json, pointer);
            for (const SchemaIssue& issue : issues)
              Emit("schema", Json(variant.file, issue.pointer), issue.message);
            if (!issues.empty()) return;
            const MetadataFrame m =
                MetadataFrameFromJson(json, variant.file, pointer);
            if (Selected("cross.metadata-pose") ||
                Selected("structure.metadata"))
              file.poses[m.index] = {m.position, m.attitude};
          });
      for (const SchemaIssue& issue :
           JsonSchema::Get("metadata.schema.json").Validate(header_json)) {
        Emit("schema", Json(variant.file, issue.pointer), issue.message);
      }
      if (frames != frames_in_file_) {
        Emit("structure.metadata",
             Json(variant.file, "/frames"),
             "has " + std::to_string(frames) + " frames, the collection " +
                 std::to_string(frames_in_file_));
      }
    } catch (const Error& e) {
      Location where = e.location();
      where.file = variant.file;  // relative, like every location of the report
      Emit("schema", where, e.message());
      continue;
    } catch (const std::exception& e) {
      Emit("schema", Location(variant.file), e.what());
      continue;
    }
    metadata_.push_back(std::move(file));
  }
}

uint64_t HashPath(const std::string& path) {
  return std::hash<std::string>()(fs::path(path).lexically_normal().string());
}

void Validator::CheckFrameStructure(const Frame& frame, size_t position) {
  const std::string pointer = "/frames/" + std::to_string(position);
  if (previous_) {
    if (frame.index == previous_->index) {
      Emit("structure.duplicate-frame",
           Json(kCollectionFile, pointer + "/index", frame.index),
           "frame index " + std::to_string(frame.index) +
               " appears twice in a row");
    } else if (frame.index < previous_->index) {
      Emit("structure.frame-order",
           Json(kCollectionFile, pointer + "/index", frame.index),
           "frame index " + std::to_string(frame.index) + " follows " +
               std::to_string(previous_->index));
    }
    if (frame.time < previous_->time && frame.sequence == previous_->sequence) {
      Emit("structure.frame-order",
           Json(kCollectionFile, pointer + "/time", frame.index),
           "time " + std::to_string(frame.time) +
               " is before the previous frame's " +
               std::to_string(previous_->time));
    }
  }
  for (const LayerInfo& layer : header_.layers) {
    const auto it = frame.files.find(layer.name);
    if (it == frame.files.end()) {
      if (layer.required) {
        Emit("structure.missing-file",
             Json(kCollectionFile, pointer + "/files", frame.index),
             "frame has no file for required layer '" + layer.name + "'");
      }
      continue;
    }
    std::error_code ec;
    if (!fs::is_regular_file(root_ / it->second, ec)) {
      Location where(it->second);
      where.frame = frame.index;
      Emit("structure.missing-file",
           where,
           "file of layer '" + layer.name + "' does not exist (referenced at " +
               kCollectionFile + "#" + pointer + "/files/" + layer.name + ")");
    }
  }
  for (const auto& [layer, file] : frame.files) {
    referenced_.insert(HashPath(file));
    layer_folders_.insert(fs::path(file).parent_path().string());
    if (header_.FindLayer(layer) == nullptr) {
      std::vector<std::string> names;
      for (const LayerInfo& l : header_.layers) names.push_back(l.name);
      Emit("structure.unknown-layer",
           Json(kCollectionFile, pointer + "/files/" + layer, frame.index),
           "layer '" + layer + "' is not in the layer table" +
               DidYouMean(layer, names));
    }
  }
  const double det = frame.camera.cam_from_world_rotation.determinant();
  const bool right = header_.conventions.world.right_handed();
  if (std::abs(std::abs(det) - 1) > 1e-6 || (det > 0) != right) {
    Emit("structure.handedness",
         Json(kCollectionFile,
              pointer + "/camera/cam_from_world/rotation",
              frame.index),
         "rotation determinant is " + std::to_string(det) +
             " but the world is declared " + (right ? "right" : "left") +
             "-handed (expected " + (right ? "+1" : "-1") + ")");
  }
  std::set<uint32_t> instances;
  for (size_t k = 0; k < frame.objects.size(); ++k) {
    const ObjectTruth& object = frame.objects[k];
    const std::string object_pointer =
        pointer + "/objects/" + std::to_string(k);
    const std::string who = "instance " + std::to_string(object.instance_id);
    if (header_.FindClass(object.class_id) == nullptr) {
      Emit("structure.class-id",
           Json(kCollectionFile, object_pointer + "/class_id", frame.index),
           "class id " + std::to_string(object.class_id) +
               " is not in the class table",
           who);
    } else {
      std::lock_guard<std::mutex> lock(tally_mutex_);
      ++objects_per_class_[object.class_id];
    }
    if (!instances.insert(object.instance_id).second) {
      Emit("structure.duplicate-instance",
           Json(kCollectionFile, object_pointer + "/instance_id", frame.index),
           "instance id " + std::to_string(object.instance_id) +
               " appears twice in the frame",
           who);
    }
    if (object.visible_pixels == 0) {
      Emit("stats.zero-visible-target",
           Json(kCollectionFile, object_pointer, frame.index),
           "object has no visible pixels but is kept as a target",
           who);
    }
  }
  if (frame.objects.empty()) {
    Emit("stats.empty-frame",
         Json(kCollectionFile, pointer + "/objects", frame.index),
         "frame has no objects");
  }
  for (MetadataFile& file : metadata_) {
    const auto it = file.poses.find(frame.index);
    if (it == file.poses.end()) {
      Emit("structure.metadata",
           Json(file.file, "/frames", frame.index),
           "has no entry for frame " + std::to_string(frame.index));
      continue;
    }
    const MetadataFrame truth = TruthMetadata(frame, header_.conventions.world);
    const double position_error = (truth.position - it->second.position).norm();
    const Eigen::Quaterniond a = NedFromBody(truth.attitude),
                             b = NedFromBody(it->second.attitude);
    const double angle_error = a.angularDistance(b) * 180 / M_PI;
    for (auto [stat, value] : {std::pair{&file.position_error, position_error},
                               {&file.angle_error, angle_error}}) {
      stat->max = std::max(stat->max, value);
      stat->sum_squares += value * value;
      ++stat->count;
    }
    if (position_error > 1e-6 || angle_error > 1e-6) {
      ++file.mismatched;
      if (!file.first_mismatch) file.first_mismatch = frame.index;
    }
    file.poses.erase(it);  // each pose is needed once
  }
}

void Validator::FlushBatch() {
  if (batch_.empty()) return;
  FrameCheckContext context;
  context.root = root_;
  context.header = &header_;
  context.checks = &options_.checks;
  context.camera_grid = options_.camera_grid;
  tbb::parallel_for(size_t{0}, batch_.size(), [&](size_t i) {
    FrameOutcome outcome = CheckFrame(context, batch_[i]);
    report_.AddAll(&outcome.findings);
    for (const auto& [name, statistic] : outcome.statistics)
      report_.MergeStatistic(name, statistic);
    std::lock_guard<std::mutex> lock(tally_mutex_);
    pixel_classes_.insert(outcome.pixel_classes.begin(),
                          outcome.pixel_classes.end());
    report_.files_decoded += outcome.files_decoded;
    report_.bytes_decoded += outcome.bytes_decoded;
  });
  batch_.clear();
}

void Validator::StreamFrames() {
  const std::string file = kCollectionFile;
  const JsonSchema& frame_schema =
      JsonSchema::Get("collection.schema.json", "frame");
  Progress progress("validate", static_cast<int64_t>(frames_in_file_));
  StreamJsonArrayMember(
      root_ / kCollectionFile,
      "frames",
      nullptr,
      [&](nlohmann::json&& json, size_t position) {
        const std::string pointer = "/frames/" + std::to_string(position);
        std::optional<int64_t> index;
        if (json.is_object() && json.contains("index") &&
            json["index"].is_number_integer()) {
          index = json["index"].get<int64_t>();
        }
        const std::vector<SchemaIssue> issues =
            frame_schema.Validate(json, pointer);
        for (const SchemaIssue& issue : issues)
          Emit("schema", Json(file, issue.pointer, index), issue.message);
        ++report_.frames;
        if (options_.progress) progress.Add();
        if (!issues.empty()) {
          previous_.reset();
          return;
        }
        Frame frame;
        try {
          frame = FrameFromJson(json, file, pointer);
        } catch (const Error& e) {
          Emit("schema",
               Json(file, e.location().json_pointer, index),
               e.message());
          previous_.reset();
          return;
        } catch (const std::exception& e) {
          Emit("schema", Json(file, pointer, index), e.what());
          previous_.reset();
          return;
        }
        CheckFrameStructure(frame, position);
        FrameInput input;
        input.position = position;
        // Motion continues within a shot (format 1.1), or within a sequence
        // in 1.0 collections, which have no shots.
        const bool same_shot =
            previous_ && (frame.shot && previous_->shot
                              ? *frame.shot == *previous_->shot
                              : previous_->sequence == frame.sequence);
        if (previous_ && previous_->index + 1 == frame.index && same_shot) {
          input.previous_camera = previous_->camera;
        }
        input.shot_start = frame.shot && *frame.shot == frame.index;
        previous_ = frame;
        previous_->objects.clear();
        previous_->files.clear();
        input.frame = std::move(frame);
        batch_.push_back(std::move(input));
        if (batch_.size() >= options_.batch_size) FlushBatch();
      });
  FlushBatch();
}

void Validator::CheckStrayFiles() {
  if (!Selected("structure.stray-file")) return;
  for (const std::string& folder : layer_folders_) {
    if (folder.empty()) continue;  // files at the root: not a layer folder
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(root_ / folder, ec)) {
      if (!entry.is_regular_file()) continue;
      const std::string relative =
          (fs::path(folder) / entry.path().filename()).string();
      if (referenced_.count(HashPath(relative)) == 0) {
        Emit("structure.stray-file",
             Location(relative),
             "no frame references this file");
      }
    }
  }
}

void Validator::CheckStatistics() {
  for (MetadataFile& file : metadata_) {
    report_.MergeStatistic(
        "cross.metadata-pose." + file.file + ".position_error",
        file.position_error);
    report_.MergeStatistic(
        "cross.metadata-pose." + file.file + ".angle_error_deg",
        file.angle_error);
    if (file.mismatched > 0 && !file.perturbed) {
      Location where(file.file, "/frames");
      where.frame = file.first_mismatch;
      Emit("cross.metadata-pose",
           where,
           std::to_string(file.mismatched) +
               " frame(s) differ from truth (max position error " +
               std::to_string(file.position_error.max) +
               " world units, max attitude error " +
               std::to_string(file.angle_error.max) +
               " deg) but the file is not declared perturbed");
    }
  }
  int64_t most = 0, least = -1;
  std::string most_name, least_name;
  const bool has_classid_layer =
      header_.FindLayerBySemantic("classid") != nullptr;
  for (size_t k = 0; k < header_.classes.size(); ++k) {
    const ClassInfo& c = header_.classes[k];
    const auto it = objects_per_class_.find(c.id);
    const int64_t n = it == objects_per_class_.end() ? 0 : it->second;
    // Without a classid layer, pixels cannot tell whether a class without
    // objects (the terrain) is drawn: only what is declared is checked.
    if (n == 0 && pixel_classes_.count(c.id) == 0 && has_classid_layer) {
      Emit("stats.class-unused",
           Json(kCollectionFile, "/classes/" + std::to_string(k)),
           "class " + std::to_string(c.id) + " '" + c.name +
               "' has no object and no pixel");
    }
    if (n > most) most = n, most_name = c.name;
    if (n > 0 && (least < 0 || n < least)) least = n, least_name = c.name;
  }
  if (least > 0 && most >= 100 * least) {
    Emit("stats.class-imbalance",
         Json(kCollectionFile, "/classes"),
         "class '" + most_name + "' has " + std::to_string(most) +
             " objects, class '" + least_name + "' only " +
             std::to_string(least));
  }
}

Report Validator::Run() {
  const auto start = std::chrono::steady_clock::now();
  report_.collection = root_.string();
  for (const CheckInfo& check : AllChecks()) {
    if (Selected(check.id)) report_.checks.push_back(check.id);
  }
  CheckCollectionFolder(root_);
  if (ReadHeader()) {
    CheckTables();
    for (const Finding& f : TruthOriginFindings(header_))
      Emit(f.check_id, f.location, f.message);
    ReadMetadata();
    StreamFrames();
    CheckStrayFiles();
    CheckStatistics();
  }
  report_.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return std::move(report_);
}

}  // namespace

Report ValidateCollection(const fs::path& root,
                          const ValidateOptions& options) {
  std::unique_ptr<tbb::global_control> threads;
  if (options.jobs > 0) {
    threads = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism,
        static_cast<size_t>(options.jobs));
  }
  return Validator(root, options).Run();
}

}  // namespace lsds::validate
