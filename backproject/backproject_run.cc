#include "backproject/backproject_run.h"

#include "libs/collection/rig.h"

#include <unistd.h>

#include <map>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include <tbb/parallel_for.h>

#include "backproject/cloud_io.h"
#include "backproject/voxel_grid.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/attitude.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"

namespace lsds::pointcloud {

namespace fs = std::filesystem;

Eigen::Affine3d WorldFromCamOfTruth(const CameraTruth& camera) {
  Eigen::Affine3d cam_from_world = Eigen::Affine3d::Identity();
  cam_from_world.linear() = camera.cam_from_world_rotation;
  cam_from_world.translation() = camera.cam_from_world_translation;
  return cam_from_world.inverse();
}

Eigen::Affine3d WorldFromCamOfMetadata(const WorldFrame& world, const MetadataFrame& m) {
  const Rigid3d enu_from_cam =
      CamFromEnu(world.EnuMetresFromWorld(m.position), m.attitude).Inverse();
  // p_world = F^T (R (s p) + t) / s = F^T R p + F^T t / s
  Eigen::Affine3d world_from_cam = Eigen::Affine3d::Identity();
  world_from_cam.linear() =
      world.enu_from_frame.transpose() * enu_from_cam.rotation.toRotationMatrix();
  world_from_cam.translation() =
      world.enu_from_frame.transpose() * enu_from_cam.translation / world.metres_per_unit;
  return world_from_cam;
}

namespace {

// The layers a run reads, from the collection's layer table.
struct Plan {
  const LayerInfo* depth = nullptr;
  const LayerInfo* rgb = nullptr;
  const LayerInfo* classid = nullptr;
  const LayerInfo* instanceid = nullptr;
  const LayerInfo* normal = nullptr;
  const LayerInfo* world = nullptr;
  DepthKind depth_kind = DepthKind::kPlanar;
  Attributes attributes;
};

std::vector<std::string> ChannelNames(const LayerInfo& layer,
                                      size_t count,
                                      const std::string& where) {
  if (layer.channels.size() < count) {
    throw Error("layer '" + layer.name + "' declares " + std::to_string(layer.channels.size()) +
                    " channels, expected " + std::to_string(count),
                Location(where));
  }
  std::vector<std::string> names;
  for (size_t i = 0; i < count; ++i) names.push_back(layer.channels[i].name);
  return names;
}

// One frame's decoded layers, owning the pixels the FrameLayers views point
// into.
struct LoadedFrame {
  exr::FlatImage depth, rgb, classid, instanceid, normal, world;
  FrameLayers layers;
  const float* world_x = nullptr;
  const float* world_y = nullptr;
  const float* world_z = nullptr;
};

const float* Floats(const exr::FlatImage& image, const std::string& channel, const fs::path& path) {
  const exr::FlatChannel& c = image.Get(channel);
  if (c.floats.size() != image.pixel_count()) {
    throw Error("channel '" + channel + "' is not HALF or FLOAT", Location(path.string()));
  }
  return c.floats.data();
}

const uint32_t* Uints(const exr::FlatImage& image,
                      const std::string& channel,
                      const fs::path& path) {
  const exr::FlatChannel& c = image.Get(channel);
  if (c.uints.size() != image.pixel_count()) {
    throw Error("channel '" + channel + "' is not UINT", Location(path.string()));
  }
  return c.uints.data();
}

void Load(const CollectionReader& reader,
          const Frame& frame,
          const LayerInfo& layer,
          size_t channels,
          int width,
          int height,
          exr::FlatImage* image,
          fs::path* path) {
  *path = reader.LayerPath(frame, layer.name);
  *image = reader.ReadFlatLayer(
      frame, layer.name, ChannelNames(layer, channels, reader.collection_path().string()));
  if (image->width() != width || image->height() != height) {
    Location where(path->string());
    where.frame = frame.index;
    throw Error("layer '" + layer.name + "' is " + std::to_string(image->width()) + "x" +
                    std::to_string(image->height()) + " but the frame's depth is " +
                    std::to_string(width) + "x" + std::to_string(height),
                where);
  }
}

LoadedFrame LoadFrame(const CollectionReader& reader,
                      const Frame& frame,
                      const Plan& plan,
                      bool check) {
  LoadedFrame f;
  fs::path path;
  const std::string depth_channel =
      ChannelNames(*plan.depth, 1, reader.collection_path().string())[0];
  path = reader.LayerPath(frame, plan.depth->name);
  f.depth = reader.ReadFlatLayer(frame, plan.depth->name, {depth_channel});
  const int w = f.depth.width(), h = f.depth.height();
  FrameLayers& l = f.layers;
  l.width = w;
  l.height = h;
  l.depth = Floats(f.depth, depth_channel, path);
  l.depth_kind = plan.depth_kind;
  if (plan.attributes.rgb) {
    Load(reader, frame, *plan.rgb, 3, w, h, &f.rgb, &path);
    const auto names = ChannelNames(*plan.rgb, 3, "");
    l.red = Floats(f.rgb, names[0], path);
    l.green = Floats(f.rgb, names[1], path);
    l.blue = Floats(f.rgb, names[2], path);
  }
  if (plan.attributes.labels) {
    Load(reader, frame, *plan.classid, 1, w, h, &f.classid, &path);
    l.class_id = Uints(f.classid, plan.classid->channels[0].name, path);
    Load(reader, frame, *plan.instanceid, 1, w, h, &f.instanceid, &path);
    l.instance_id = Uints(f.instanceid, plan.instanceid->channels[0].name, path);
  }
  if (plan.attributes.normals) {
    Load(reader, frame, *plan.normal, 3, w, h, &f.normal, &path);
    const auto names = ChannelNames(*plan.normal, 3, "");
    l.normal_x = Floats(f.normal, names[0], path);
    l.normal_y = Floats(f.normal, names[1], path);
    l.normal_z = Floats(f.normal, names[2], path);
  }
  if (check) {
    Load(reader, frame, *plan.world, 3, w, h, &f.world, &path);
    const auto names = ChannelNames(*plan.world, 3, "");
    f.world_x = Floats(f.world, names[0], path);
    f.world_y = Floats(f.world, names[1], path);
    f.world_z = Floats(f.world, names[2], path);
  }
  return f;
}

fs::path ResolveMetadataPath(const fs::path& root, const fs::path& file) {
  std::error_code ec;
  if (file.is_relative() && !fs::exists(file, ec) && fs::exists(root / file, ec))
    return root / file;
  return file;
}

// Fails early (before any work) when a file cannot be created beside `path`.
void CheckWritableParent(const fs::path& path) {
  const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw Error("output folder does not exist", Location(parent.string()));
  if (::access(parent.c_str(), W_OK) != 0) {
    throw Error("output folder is not writable", Location(parent.string()));
  }
}

struct FrameResult {
  PointCloud cloud;
  FrameReport report;
};

void CheckOptions(const BackprojectOptions& options) {
  if (options.stride < 1) throw Error("--stride must be >= 1");
  if (options.voxel < 0) throw Error("--voxel must be >= 0");
  if (options.voxel > 0 && !options.fuse)
    throw Error("--voxel needs --fuse (it downsamples the fused cloud)");
  if (options.output.empty() && !options.check)
    throw Error("nothing to do: give -o OUT, --check or both");
}

std::string LayerNames(const CollectionHeader& header) {
  std::vector<std::string> names;
  for (const LayerInfo& l : header.layers) names.push_back(l.name);
  return Join(names, ", ");
}

Plan PlanLayers(const CollectionHeader& header,
                const BackprojectOptions& options,
                const std::string& collection_file) {
  Plan plan;
  plan.depth = header.FindLayerBySemantic("depth");
  if (plan.depth == nullptr || plan.depth->deep) {
    throw Error("the collection has no flat depth layer to back-project (layers: " +
                    LayerNames(header) + ")",
                Location(collection_file, "/layers"));
  }
  plan.depth_kind = plan.depth->depth_kind.value_or(DepthKind::kPlanar);
  plan.rgb = header.FindLayerBySemantic("rgb");
  plan.classid = header.FindLayerBySemantic("classid");
  plan.instanceid = header.FindLayerBySemantic("instanceid");
  plan.normal = header.FindLayerBySemantic("normal");
  plan.world = header.FindLayerBySemantic("worldposition");
  plan.attributes.rgb = options.colors && plan.rgb != nullptr;
  plan.attributes.labels = options.labels && plan.classid != nullptr && plan.instanceid != nullptr;
  plan.attributes.normals = options.normals;
  if (options.normals && plan.normal == nullptr) {
    throw Error("--normals: the collection has no normal layer",
                Location(collection_file, "/layers"));
  }
  if (options.check && plan.world == nullptr) {
    throw Error("--check: the collection has no worldposition layer to compare with",
                Location(collection_file, "/layers"));
  }
  return plan;
}

// Poses from a metadata variant, by frame index (a few numbers per frame).
struct MetadataPoses {
  fs::path path;
  std::map<int64_t, MetadataFrame> frames;
};

MetadataPoses ReadMetadataPoses(const CollectionReader& reader, const BackprojectOptions& options) {
  MetadataPoses poses;
  if (options.metadata.empty()) return poses;
  poses.path = ResolveMetadataPath(reader.root(), options.metadata);
  const MetadataReader metadata_reader(poses.path);
  metadata_reader.ForEachFrame([&](const MetadataFrame& m) {
    if (options.frames.Contains(m.index)) poses.frames[m.index] = m;
  });
  return poses;
}

// The outputs of a run: one fused file, or a folder of one cloud per frame.
struct Outputs {
  std::optional<CloudFormat> format;
  std::unique_ptr<AtomicDirectory> folder;
};

// Outputs: checked and claimed before any work, so that bad usage costs
// nothing.
Outputs ClaimOutputs(const BackprojectOptions& options) {
  Outputs outputs;
  if (options.output.empty()) return outputs;
  if (options.fuse) {
    outputs.format = FormatFromPath(options.output);
    RefuseToOverwrite(options.output, options.force);
    CheckWritableParent(options.output);
    return outputs;
  }
  const std::string ext = options.output.extension().string();
  if (ext == ".pcd" || ext == ".ply" || ext == ".PCD" || ext == ".PLY") {
    throw Error(
        "without --fuse the output is a folder of one cloud per frame; add "
        "--fuse to write one file, select one frame (--frames N), or name "
        "a folder (and --format pcd|ply)",
        Location(options.output.string()));
  }
  outputs.format = FormatFromName(options.per_frame_format);
  CheckWritableParent(options.output);
  outputs.folder = std::make_unique<AtomicDirectory>(options.output, options.force);
  return outputs;
}

// One run of `lsds backproject`: the options checked, the layers planned and
// the outputs claimed on construction; then the frames streamed in batches.
class BackprojectRun {
 public:
  BackprojectRun(const BackprojectOptions& options,
                 const std::function<void(const FrameReport&)>& on_frame)
      : options_((CheckOptions(options), options)),
        on_frame_(on_frame),
        reader_(options.collection),
        collection_file_(reader_.collection_path().string()),
        plan_(PlanLayers(reader_.header(), options, collection_file_)),
        world_(reader_.header().conventions.world),
        metadata_(ReadMetadataPoses(reader_, options)),
        outputs_(ClaimOutputs(options)) {
    summary_.world_unit = world_.length_unit;
    fused_.attributes = plan_.attributes;
    if (options_.fuse && options_.voxel > 0)
      voxels_ = std::make_unique<VoxelAccumulator>(options_.voxel, plan_.attributes);
  }

  BackprojectSummary Run();

 private:
  Eigen::Affine3d WorldFromCam(const Frame& frame, FramePose* pose) const;
  FrameResult ProcessFrame(const Frame& frame) const;
  void Flush(std::vector<Frame>* batch, Progress* progress);
  void Keep(FrameResult* result);
  void WriteFused();

  const BackprojectOptions& options_;
  const std::function<void(const FrameReport&)>& on_frame_;
  const CollectionReader reader_;
  const std::string collection_file_;
  const Plan plan_;
  const WorldFrame& world_;
  const MetadataPoses metadata_;
  Outputs outputs_;
  BackprojectSummary summary_;
  PointCloud fused_;
  std::unique_ptr<VoxelAccumulator> voxels_;
};

// The camera's pose of the frame: the truth, or the metadata variant's when
// one is given (with its intrinsics, when it has them).
Eigen::Affine3d BackprojectRun::WorldFromCam(const Frame& frame, FramePose* pose) const {
  if (options_.metadata.empty()) return WorldFromCamOfTruth(frame.camera);
  const auto it = metadata_.frames.find(frame.index);
  if (it == metadata_.frames.end()) {
    Location where(metadata_.path.string());
    where.frame = frame.index;
    throw Error("the metadata variant has no frame " + std::to_string(frame.index), where);
  }
  if (it->second.camera.width > 0) pose->camera = it->second.camera;
  return WorldFromCamOfMetadata(world_, it->second);
}

FrameResult BackprojectRun::ProcessFrame(const Frame& frame) const {
  FrameResult result;
  result.report.index = frame.index;
  result.report.stem = FrameFileStem(frame);
  result.cloud.attributes = plan_.attributes;
  const LoadedFrame loaded = LoadFrame(reader_, frame, plan_, options_.check);
  FramePose pose;
  pose.camera = frame.camera.intrinsics;
  const Eigen::Affine3d cam_from_world_truth = WorldFromCamOfTruth(frame.camera).inverse();
  const Eigen::Affine3d world_from_cam = WorldFromCam(frame, &pose);
  if (pose.camera.width != loaded.layers.width || pose.camera.height != loaded.layers.height) {
    Location where(reader_.LayerPath(frame, plan_.depth->name).string());
    where.frame = frame.index;
    throw Error("depth is " + std::to_string(loaded.layers.width) + "x" +
                    std::to_string(loaded.layers.height) + " but the camera is " +
                    std::to_string(pose.camera.width) + "x" + std::to_string(pose.camera.height),
                where);
  }
  if (options_.frame == OutputFrame::kWorld) {
    pose.out_from_cam = world_from_cam;
    pose.out_from_world_normal = world_from_cam.linear() * cam_from_world_truth.linear();
  } else {
    pose.out_from_cam = Eigen::Affine3d::Identity();
    pose.out_from_world_normal = cam_from_world_truth.linear();
  }
  if (!options_.output.empty())
    BackprojectFrame(loaded.layers, pose, options_.stride, &result.cloud);
  if (options_.check) {
    result.report.checked = true;
    result.report.check = CompareWithWorldPosition(loaded.layers,
                                                   pose.camera,
                                                   world_from_cam,
                                                   options_.stride,
                                                   loaded.world_x,
                                                   loaded.world_y,
                                                   loaded.world_z);
  }
  result.report.points = static_cast<int64_t>(result.cloud.points.size());
  return result;
}

// One frame's cloud into the outputs: its own file, the voxel grid or the
// fused cloud.
void BackprojectRun::Keep(FrameResult* result) {
  ++summary_.frames;
  summary_.points_backprojected += result->report.points;
  if (result->report.checked) summary_.check.Merge(result->report.check);
  if (outputs_.folder) {
    WriteCloud(outputs_.folder->temp_path() / (result->report.stem + Extension(*outputs_.format)),
               result->cloud,
               *outputs_.format,
               options_.ply_ids);
    summary_.points_written += result->report.points;
  } else if (voxels_) {
    voxels_->Add(result->cloud);
  } else if (options_.fuse && !options_.output.empty()) {
    PointVector& points = result->cloud.points;
    if (fused_.points.empty()) {
      fused_.points.swap(points);  // the first frame: no copy
    } else {
      fused_.points.insert(fused_.points.end(), points.begin(), points.end());
    }
  }
  result->cloud = PointCloud();
}

void BackprojectRun::Flush(std::vector<Frame>* batch, Progress* progress) {
  std::vector<FrameResult> results(batch->size());
  tbb::parallel_for(
      size_t{0}, batch->size(), [&](size_t i) { results[i] = ProcessFrame((*batch)[i]); });
  for (FrameResult& r : results) {
    Keep(&r);
    if (on_frame_) on_frame_(r.report);
    progress->Add();
  }
  batch->clear();
}

void BackprojectRun::WriteFused() {
  if (voxels_) fused_ = voxels_->Finish();
  summary_.points_written = static_cast<int64_t>(fused_.points.size());
  WriteCloud(options_.output, fused_, *outputs_.format, options_.ply_ids);
}

BackprojectSummary BackprojectRun::Run() {
  const int64_t in_file = static_cast<int64_t>(reader_.frames_in_file());
  const int64_t total = std::max<int64_t>(
      0, std::min(in_file, options_.frames.end) - std::min(in_file, options_.frames.begin));
  Progress progress("backproject", total);

  // Frames are streamed in batches back-projected in parallel, then merged in
  // file order, so the output is deterministic and memory holds one batch of
  // frames plus the output cloud.
  const size_t batch_size =
      options_.batch_frames > 0
          ? options_.batch_frames
          : std::max<size_t>(2, size_t{2} * std::thread::hardware_concurrency());
  std::vector<Frame> batch;
  reader_.ForEachFrame([&](const Frame& frame) {
    if (!options_.frames.Contains(frame.index)) return;
    batch.push_back(frame);
    if (batch.size() >= batch_size) Flush(&batch, &progress);
  });
  Flush(&batch, &progress);
  if (summary_.frames == 0) {
    throw Error("no frame selected (the collection has " + std::to_string(in_file) + " frames)",
                Location(collection_file_));
  }
  if (options_.fuse && !options_.output.empty()) WriteFused();
  if (outputs_.folder) outputs_.folder->Commit();
  return summary_;
}

}  // namespace

BackprojectSummary RunBackproject(const BackprojectOptions& options,
                                  const std::function<void(const FrameReport&)>& on_frame) {
  return BackprojectRun(options, on_frame).Run();
}

}  // namespace lsds::pointcloud
