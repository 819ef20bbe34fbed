#include "validators/validate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "libs/collection/collection_reader.h"
#include "libs/collection/file_sizes.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/rig.h"
#include "libs/collection/schema.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"
#include "validators/compact_tables.h"
#include "validators/cycles_agreement_check.h"
#include "validators/frame_checks.h"
#include "validators/truth_origin_check.h"

namespace lsds::validate {

namespace fs = std::filesystem;

namespace {

class Validator {
 public:
  Validator(const fs::path& root, const ValidateOptions& options)
      : root_(root), options_(options), report_(options.max_examples) {}

  // Runs the checks; with `finish`, also the whole-collection checks (a
  // single run), else their tallies are left for the join of the shards.
  Report Run(bool finish);
  const CollectionTallies& tallies() const { return tallies_; }

 private:
  bool Selected(const std::string& id) const { return options_.checks.Has(id); }
  // Findings are emitted only for what this shard owns (see emitting_).
  void Emit(const std::string& id,
            Location location,
            const std::string& message,
            const std::string& object = "") {
    if (!emitting_ || !Selected(id)) return;
    report_.Add({GetCheck(id).severity, id, std::move(location), object, message});
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
  void CheckReadFrame(Frame&& frame, size_t position, bool owned);
  void CheckFrameStructure(const Frame& frame, size_t position);
  void CheckFrameOrder(const Frame& frame, const std::string& pointer);
  void CheckFrameFiles(const Frame& frame, const std::string& pointer);
  void CheckFrameHandedness(const Frame& frame, const std::string& pointer);
  void CheckFrameObjects(const Frame& frame, const std::string& pointer);
  void CheckFrameMetadata(const Frame& frame);
  void FlushBatch();
  void CheckStrayFiles();
  bool OwnsFrame(std::optional<int64_t> index) const;
  // The selected ones of `ids`, for a CheckTimer.
  std::vector<std::string> SelectedOf(std::vector<std::string> ids) const;
  void AddCheckSeconds();

  fs::path root_;
  FileSizes file_sizes_{root_};  // the layer files' stat, their folders opened once
  ValidateOptions options_;
  Report report_;
  CollectionHeader header_;
  size_t frames_in_file_ = 0;
  // Shard I of N emits the findings of the frames it owns and (I = 0) those
  // about the collection as a whole; a single run is shard 0 of 1.
  bool emitting_ = true;
  bool shard_zero_ = true;
  CheckSeconds check_seconds_;  // this thread

  // Streaming state: O(1) per frame except the hashes of referenced files (8
  // bytes per file) and the compact metadata poses (one per frame), both
  // documented in docs/validate.md.
  std::vector<FrameInput> batch_;
  std::optional<Frame> previous_;  // the frame before, for order checks
  // The last frame of each camera stream (libs/collection/rig.h) and its
  // object boxes, for the frame-to-frame checks (motion).
  struct PreviousFrame {
    Frame frame;
    std::map<uint32_t, OrientedBox> boxes;
  };
  std::map<std::string, PreviousFrame> previous_by_camera_;
  std::optional<std::pair<int64_t, Rigid3d>> rig_pose_;  // the current step's platform pose
  void CheckRigFrame(const Frame& frame, const std::string& pointer);
  HashSet64 referenced_;  // hashes of the files frames reference
  std::set<std::string> layer_folders_;
  struct MetadataPose {
    Eigen::Vector3d position;
    Attitude attitude;
  };
  struct MetadataFile {
    std::string file;
    FrameTable<MetadataPose> poses;
    size_t tally = 0;  // its entry in tallies_.metadata
  };
  std::vector<MetadataFile> metadata_;
  CollectionTallies tallies_;  // of the frames this shard owns
  std::mutex tally_mutex_;
};

bool Validator::ReadHeader() {
  nlohmann::json header_json;
  // Syntax errors throw lsds::Error with line:column: the input cannot be read
  // as a collection.
  frames_in_file_ = ReadCollectionHeader(root_ / kCollectionFile, &header_json);
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
      Emit("schema", Json(kCollectionFile, "/"), std::string("header cannot be read: ") + e.what());
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
    if ((layer.semantic == "depth" || layer.semantic == "bundle") && !layer.depth_kind) {
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
         "frame_count is " + std::to_string(header_.frame_count) + " but the file has " +
             std::to_string(frames_in_file_) + " frames");
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
    if (Selected("cross.metadata-pose") || Selected("structure.metadata"))
      file.poses.Reserve(frames_in_file_);  // metadata.json has a pose per frame
    CollectionTallies::Metadata tally;
    tally.file = variant.file;
    tally.perturbed = variant.perturbed;
    try {
      nlohmann::json header_json;
      const JsonSchema& frame_schema = JsonSchema::Get("metadata.schema.json", "frame");
      const size_t frames = StreamJsonArrayMember(
          path, "frames", &header_json, [&](nlohmann::json&& json, size_t index) {
            const std::string pointer = "/frames/" + std::to_string(index);
            const auto issues = frame_schema.Validate(json, pointer);
            for (const SchemaIssue& issue : issues)
              Emit("schema", Json(variant.file, issue.pointer), issue.message);
            if (!issues.empty()) return;
            const MetadataFrame m = MetadataFrameFromJson(json, variant.file, pointer);
            if (Selected("cross.metadata-pose") || Selected("structure.metadata"))
              file.poses.Add(m.index, {m.position, m.attitude});
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
    file.tally = tallies_.metadata.size();
    tallies_.metadata.push_back(std::move(tally));
    metadata_.push_back(std::move(file));
  }
}

uint64_t HashPath(const std::string& path) {
  return std::hash<std::string>()(fs::path(path).lexically_normal().string());
}

// A rig frame (docs/format.md, "Camera rigs"): a rig camera of the header, a
// time step, that camera's intrinsics, and the platform pose
// rig_from_world = inverse(cam_from_rig) * cam_from_world the same for every
// camera of the step.
void Validator::CheckRigFrame(const Frame& frame, const std::string& pointer) {
  if (!Selected("structure.rig")) return;
  const bool rig = header_.rig.has_value();
  if (!rig) {
    if (frame.rig_camera || frame.step)
      Emit(
          "structure.rig",
          Json(
              kCollectionFile, pointer + (frame.rig_camera ? "/rig_camera" : "/step"), frame.index),
          "the frame names a rig camera or step but collection.json has no rig");
    return;
  }
  const RigCamera* camera = frame.rig_camera ? header_.rig->Find(*frame.rig_camera) : nullptr;
  if (!camera || !frame.step) {
    Emit("structure.rig",
         Json(kCollectionFile, pointer + (camera ? "/step" : "/rig_camera"), frame.index),
         camera ? "a rig frame needs its time step"
                : "the frame names no camera of the rig ('" + frame.rig_camera.value_or("") + "')");
    return;
  }
  const PinholeCamera& k = frame.camera.intrinsics;
  const PinholeCamera& r = camera->intrinsics;
  auto close = [](double a, double b) {
    return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b));
  };
  if (k.width != r.width || k.height != r.height || !close(k.fx, r.fx) || !close(k.fy, r.fy) ||
      !close(k.cx, r.cx) || !close(k.cy, r.cy))
    Emit("structure.rig",
         Json(kCollectionFile, pointer + "/camera", frame.index),
         "the frame's intrinsics differ from rig camera '" + camera->name + "'");
  Rigid3d cam_from_world(Eigen::Quaterniond(frame.camera.cam_from_world_rotation).normalized(),
                         frame.camera.cam_from_world_translation);
  const Rigid3d rig_from_world = camera->cam_from_rig.Inverse() * cam_from_world;
  if (!rig_pose_ || rig_pose_->first != *frame.step) {
    rig_pose_ = std::make_pair(*frame.step, rig_from_world);
    return;
  }
  const Rigid3d& first = rig_pose_->second;
  const double angle = first.rotation.angularDistance(rig_from_world.rotation);
  const double scale = std::max(1.0, first.translation.norm());
  if (angle > 1e-6 || (first.translation - rig_from_world.translation).norm() > 1e-6 * scale)
    Emit("structure.rig",
         Json(kCollectionFile, pointer + "/camera/cam_from_world", frame.index),
         "rig camera '" + camera->name + "' at step " + std::to_string(*frame.step) +
             " puts the platform elsewhere than the step's first camera (" +
             FormatNumber(angle * 180 / M_PI) + " deg, " +
             FormatNumber((first.translation - rig_from_world.translation).norm()) + " apart)");
}

// One frame's entry in collection.json, each aspect a method: its order after the previous
// frame, its layer files, its camera's handedness, its objects, and its metadata poses.
void Validator::CheckFrameStructure(const Frame& frame, size_t position) {
  const std::string pointer = "/frames/" + std::to_string(position);
  CheckRigFrame(frame, pointer);
  CheckFrameOrder(frame, pointer);
  CheckFrameFiles(frame, pointer);
  CheckFrameHandedness(frame, pointer);
  CheckFrameObjects(frame, pointer);
  CheckFrameMetadata(frame);
  if (emitting_ && !header_.provenance.requirements.is_null()) {
    std::lock_guard<std::mutex> lock(tally_mutex_);
    AddRequirementSummary(header_.provenance.requirements, frame, &tallies_.requirements);
  }
}

// Frame indices strictly increase; time does not go back within a sequence.
void Validator::CheckFrameOrder(const Frame& frame, const std::string& pointer) {
  if (previous_) {
    if (frame.index == previous_->index) {
      Emit("structure.duplicate-frame",
           Json(kCollectionFile, pointer + "/index", frame.index),
           "frame index " + std::to_string(frame.index) + " appears twice in a row");
    } else if (frame.index < previous_->index) {
      Emit("structure.frame-order",
           Json(kCollectionFile, pointer + "/index", frame.index),
           "frame index " + std::to_string(frame.index) + " follows " +
               std::to_string(previous_->index));
    }
    if (frame.time < previous_->time && frame.sequence == previous_->sequence) {
      Emit("structure.frame-order",
           Json(kCollectionFile, pointer + "/time", frame.index),
           "time " + std::to_string(frame.time) + " is before the previous frame's " +
               std::to_string(previous_->time));
    }
  }
}

// Every required layer has a file, every file exists, every file's layer is in the table.
void Validator::CheckFrameFiles(const Frame& frame, const std::string& pointer) {
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
    if (!file_sizes_.Size(it->second)) {  // no regular file there
      Location where(it->second);
      where.frame = frame.index;
      Emit("structure.missing-file",
           where,
           "file of layer '" + layer.name + "' does not exist (referenced at " + kCollectionFile +
               "#" + pointer + "/files/" + layer.name + ")");
    }
  }
  for (const auto& [layer, file] : frame.files) {
    referenced_.Insert(HashPath(file));
    layer_folders_.insert(fs::path(file).parent_path().string());
    if (header_.FindLayer(layer) == nullptr) {
      std::vector<std::string> names;
      for (const LayerInfo& l : header_.layers) names.push_back(l.name);
      Emit("structure.unknown-layer",
           Json(kCollectionFile, pointer + "/files/" + layer, frame.index),
           "layer '" + layer + "' is not in the layer table" + DidYouMean(layer, names));
    }
  }
}

// The camera's rotation is proper and of the world's handedness.
void Validator::CheckFrameHandedness(const Frame& frame, const std::string& pointer) {
  const double det = frame.camera.cam_from_world_rotation.determinant();
  const bool right = header_.conventions.world.right_handed();
  if (std::abs(std::abs(det) - 1) > 1e-6 || (det > 0) != right) {
    Emit("structure.handedness",
         Json(kCollectionFile, pointer + "/camera/cam_from_world/rotation", frame.index),
         "rotation determinant is " + std::to_string(det) + " but the world is declared " +
             (right ? "right" : "left") + "-handed (expected " + (right ? "+1" : "-1") + ")");
  }
}

// Known classes, unique instance ids, visible targets, at least one object.
void Validator::CheckFrameObjects(const Frame& frame, const std::string& pointer) {
  std::set<uint32_t> instances;
  for (size_t k = 0; k < frame.objects.size(); ++k) {
    const ObjectTruth& object = frame.objects[k];
    const std::string object_pointer = pointer + "/objects/" + std::to_string(k);
    const std::string who = "instance " + std::to_string(object.instance_id);
    if (header_.FindClass(object.class_id) == nullptr) {
      Emit("structure.class-id",
           Json(kCollectionFile, object_pointer + "/class_id", frame.index),
           "class id " + std::to_string(object.class_id) + " is not in the class table",
           who);
    } else if (emitting_) {
      std::lock_guard<std::mutex> lock(tally_mutex_);
      ++tallies_.objects_per_class[object.class_id];
    }
    if (!instances.insert(object.instance_id).second) {
      Emit("structure.duplicate-instance",
           Json(kCollectionFile, object_pointer + "/instance_id", frame.index),
           "instance id " + std::to_string(object.instance_id) + " appears twice in the frame",
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
}

// Each metadata file has the frame's pose; its error against the truth is tallied.
void Validator::CheckFrameMetadata(const Frame& frame) {
  for (MetadataFile& file : metadata_) {
    const MetadataPose* pose = file.poses.Take(frame.index);  // each pose is needed once
    if (pose == nullptr) {
      Emit("structure.metadata",
           Json(file.file, "/frames", frame.index),
           "has no entry for frame " + std::to_string(frame.index));
      continue;
    }
    if (!emitting_) continue;  // another shard's frame: its pose is compared there
    CollectionTallies::Metadata& tally = tallies_.metadata[file.tally];
    const MetadataFrame truth = TruthMetadata(frame, header_.conventions.world);
    const double position_error = (truth.position - pose->position).norm();
    const Eigen::Quaterniond a = NedFromBody(truth.attitude), b = NedFromBody(pose->attitude);
    const double angle_error = a.angularDistance(b) * 180 / M_PI;
    for (auto [stat, value] :
         {std::pair{&tally.position_error, position_error}, {&tally.angle_error, angle_error}}) {
      stat->max = std::max(stat->max, value);
      stat->sum_squares += value * value;
      ++stat->count;
    }
    if (position_error > 1e-6 || angle_error > 1e-6) {
      ++tally.mismatched;
      if (!tally.first_mismatch || frame.index < *tally.first_mismatch)
        tally.first_mismatch = frame.index;
    }
  }
}

void Validator::FlushBatch() {
  if (batch_.empty()) return;
  FrameCheckContext context;
  context.root = root_;
  context.header = &header_;
  context.checks = &options_.checks;
  context.camera_grid = options_.camera_grid;
  std::vector<FrameOutcome> outcomes(batch_.size());
  tbb::parallel_for(
      size_t{0}, batch_.size(), [&](size_t i) { outcomes[i] = CheckFrame(context, batch_[i]); });
  // Folded in frame order, so that sums (and so the report) do not depend on
  // which thread finished first.
  for (FrameOutcome& outcome : outcomes) {
    report_.AddAll(&outcome.findings);
    for (const auto& [name, statistic] : outcome.statistics)
      report_.MergeStatistic(name, statistic);
    for (const auto& [id, seconds] : outcome.check_seconds) report_.AddCheckSeconds(id, seconds);
    tallies_.pixel_classes.insert(outcome.pixel_classes.begin(), outcome.pixel_classes.end());
    report_.files_decoded += outcome.files_decoded;
    report_.bytes_decoded += outcome.bytes_decoded;
  }
  batch_.clear();
}

// What every frame goes through once read, by either path: the structure
// checks, then (frames this shard owns) its layers in batches.
void Validator::CheckReadFrame(Frame&& frame, size_t position, bool owned) {
  {
    CheckTimer timer(&check_seconds_,
                     owned ? SelectedOf({"structure.duplicate-frame",
                                         "structure.rig",
                                         "structure.frame-order",
                                         "structure.missing-file",
                                         "structure.unknown-layer",
                                         "structure.handedness",
                                         "structure.class-id",
                                         "structure.duplicate-instance",
                                         "structure.metadata",
                                         "cross.metadata-pose",
                                         "stats.zero-visible-target",
                                         "stats.empty-frame"})
                           : std::vector<std::string>{});
    CheckFrameStructure(frame, position);
  }
  FrameInput input;
  input.position = position;
  // Motion continues within a shot (format 1.1), or within a sequence
  // in 1.0 collections, which have no shots.
  // In a rig, against the previous frame of the same camera.
  const std::string stream = CameraStreamOf(frame);
  const auto before = previous_by_camera_.find(stream);
  if (before != previous_by_camera_.end() && ContinuesShot(before->second.frame, frame)) {
    input.previous_camera = before->second.frame.camera;
    input.previous_boxes = before->second.boxes;
  }
  input.shot_start = frame.shot && *frame.shot == frame.index;
  PreviousFrame& remembered = previous_by_camera_[stream];
  remembered.boxes.clear();
  for (const ObjectTruth& o : frame.objects)
    if (o.obb) remembered.boxes[o.instance_id] = *o.obb;
  {
    // The frame remembered without its objects and files (not copied only
    // to be cleared: they are most of a frame's allocations).
    std::vector<ObjectTruth> objects = std::move(frame.objects);
    auto files = std::move(frame.files);
    frame.objects.clear();
    frame.files.clear();
    previous_ = frame;
    remembered.frame = frame;
    frame.objects = std::move(objects);
    frame.files = std::move(files);
  }
  if (!owned) return;  // another shard decodes its layers
  input.frame = std::move(frame);
  batch_.push_back(std::move(input));
  if (batch_.size() >= options_.batch_size) FlushBatch();
}

void Validator::StreamFrames() {
  const std::string file = kCollectionFile;
  const JsonSchema& frame_schema = JsonSchema::Get("collection.schema.json", "frame");
  Progress progress("validate", static_cast<int64_t>(frames_in_file_));
  StreamCollectionFrames(
      root_ / kCollectionFile,
      [&](Frame&& frame, size_t position) {
        // The fast path took it: it passed the frame schema's checks (timed
        // as part of reading it).
        const bool owned = OwnsFrame(frame.index);
        emitting_ = owned;
        {
          const CheckTimer timer(&check_seconds_,
                                 owned ? SelectedOf({"schema"}) : std::vector<std::string>{});
        }
        if (owned) ++report_.frames;
        if (options_.progress) progress.Add();
        CheckReadFrame(std::move(frame), position, owned);
      },
      [&](nlohmann::json&& json, size_t position) {
        const std::string pointer = "/frames/" + std::to_string(position);
        std::optional<int64_t> index;
        if (json.is_object() && json.contains("index") && json["index"].is_number_integer()) {
          index = json["index"].get<int64_t>();
        }
        const bool owned = OwnsFrame(index);
        emitting_ = owned;
        std::vector<SchemaIssue> issues;
        {
          CheckTimer timer(&check_seconds_,
                           owned ? SelectedOf({"schema"}) : std::vector<std::string>{});
          issues = frame_schema.Validate(json, pointer);
        }
        for (const SchemaIssue& issue : issues)
          Emit("schema", Json(file, issue.pointer, index), issue.message);
        if (owned) ++report_.frames;
        if (options_.progress) progress.Add();
        if (!issues.empty()) {
          previous_.reset();
          previous_by_camera_.clear();
          return;
        }
        Frame frame;
        try {
          frame = FrameFromJson(json, file, pointer);
        } catch (const Error& e) {
          Emit("schema", Json(file, e.location().json_pointer, index), e.message());
          previous_.reset();
          previous_by_camera_.clear();
          return;
        } catch (const std::exception& e) {
          Emit("schema", Json(file, pointer, index), e.what());
          previous_.reset();
          previous_by_camera_.clear();
          return;
        }
        CheckReadFrame(std::move(frame), position, owned);
      });
  FlushBatch();
  emitting_ = shard_zero_;
}

void Validator::CheckStrayFiles() {
  if (!Selected("structure.stray-file")) return;
  for (const std::string& folder : layer_folders_) {
    if (folder.empty()) continue;  // files at the root: not a layer folder
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(root_ / folder, ec)) {
      if (!entry.is_regular_file()) continue;
      const std::string relative = (fs::path(folder) / entry.path().filename()).string();
      if (!referenced_.Contains(HashPath(relative))) {
        Emit("structure.stray-file", Location(relative), "no frame references this file");
      }
    }
  }
}

bool Validator::OwnsFrame(std::optional<int64_t> index) const {
  // A frame whose index cannot be read belongs to shard 0, with the findings
  // about the collection as a whole.
  if (!index) return shard_zero_;
  const int64_t n = options_.shard_count;
  return ((*index % n) + n) % n == options_.shard_index && options_.frames.Contains(*index);
}

std::vector<std::string> Validator::SelectedOf(std::vector<std::string> ids) const {
  ids.erase(
      std::remove_if(ids.begin(), ids.end(), [&](const std::string& id) { return !Selected(id); }),
      ids.end());
  return ids;
}

void Validator::AddCheckSeconds() {
  for (const auto& [id, seconds] : check_seconds_) report_.AddCheckSeconds(id, seconds);
  check_seconds_.clear();
}

Report Validator::Run(bool finish) {
  const auto start = std::chrono::steady_clock::now();
  report_.collection = root_.string();
  for (const CheckInfo& check : AllChecks()) {
    if (Selected(check.id)) report_.checks.push_back(check.id);
  }
  shard_zero_ = options_.shard_index == 0;
  emitting_ = shard_zero_;
  CheckCollectionFolder(root_);
  bool header_read = false;
  {
    CheckTimer timer(&check_seconds_,
                     shard_zero_ ? SelectedOf({"schema",
                                               "structure.tables",
                                               "structure.frame-count",
                                               "structure.truth-origin",
                                               "structure.cycles-agreement"})
                                 : std::vector<std::string>{});
    header_read = ReadHeader();
    if (header_read) {
      CheckTables();
      for (const Finding& f : TruthOriginFindings(header_)) Emit(f.check_id, f.location, f.message);
      for (const Finding& f : CyclesAgreementFindings(header_))
        Emit(f.check_id, f.location, f.message);
    }
  }
  if (header_read) {
    tallies_.header_read = true;
    tallies_.classes = header_.classes;
    tallies_.has_classid_layer = header_.FindLayerBySemantic("classid") != nullptr;
    tallies_.requirements_asked = header_.provenance.requirements;
    {
      CheckTimer timer(
          &check_seconds_,
          shard_zero_ ? SelectedOf({"schema", "structure.metadata"}) : std::vector<std::string>{});
      ReadMetadata();
    }
    StreamFrames();
    {
      CheckTimer timer(
          &check_seconds_,
          shard_zero_ ? SelectedOf({"structure.stray-file"}) : std::vector<std::string>{});
      CheckStrayFiles();
    }
    if (finish) {
      CheckTimer timer(
          &check_seconds_,
          SelectedOf({"stats.class-unused", "stats.class-imbalance", "cross.metadata-pose"}));
      FinishCollectionChecks(tallies_, options_.checks, &report_);
    }
  }
  AddCheckSeconds();
  report_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::move(report_);
}

}  // namespace

Report ValidateCollection(const fs::path& root, const ValidateOptions& options) {
  const ThreadLimit thread_limit(options.jobs);
  if (options.shard_count != 1 || options.shard_index != 0)
    throw Error("ValidateCollection runs one whole run; use ValidateShard");
  return Validator(root, options).Run(/*finish=*/true);
}

PartialReport ValidateShard(const fs::path& root, const ValidateOptions& options) {
  if (options.shard_count < 1 || options.shard_index < 0 ||
      options.shard_index >= options.shard_count) {
    throw Error("shard " + std::to_string(options.shard_index) + "/" +
                std::to_string(options.shard_count) + " is not a shard: I/N needs 0 <= I < N");
  }
  const ThreadLimit thread_limit(options.jobs);
  Validator validator(root, options);
  PartialReport partial;
  partial.report = validator.Run(/*finish=*/false);
  partial.tallies = validator.tallies();
  partial.shard_index = options.shard_index;
  partial.shard_count = options.shard_count;
  partial.collection = root.string();
  partial.checks = partial.report.checks;
  std::error_code ec;
  partial.collection_digest = fs::is_regular_file(root / kCollectionFile, ec)
                                  ? FileDigest(root / kCollectionFile)
                                  : std::string();
  return partial;
}

}  // namespace lsds::validate
