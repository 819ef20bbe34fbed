#include "generator/generate.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "generator/cycles/blender.h"
#include "generator/cycles/cycles_frame.h"
#include "generator/lang/requirements.h"
#include "generator/plan/plan_json.h"
#include "generator/render/embree_abi.h"
#include "generator/render/embree_scene.h"
#include "generator/render/exposure.h"
#include "generator/render/film.h"
#include "generator/render/integrator.h"
#include "generator/render/post_process.h"
#include "generator/render/sky.h"
#include "generator/render/truth.h"
#include "generator/scene_export/scene_export.h"
#include "generator/survey.h"
#include "libs/collection/collection_builder.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/encoder_settings.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/limits.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Per-frame truth of finished frames lives here until collection.json is
// assembled; a frame counts as complete for --resume only when its truth file
// exists (it is written after the frame's EXRs).
constexpr const char* kWorkFolder = ".lsds-generate";

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

nlohmann::json RenderSettingsJson(const GenerateOptions& options) {
  if (options.renderer == Renderer::kCycles) {
    nlohmann::json settings = RenderSettingsJson([&options] {
      GenerateOptions reference = options;
      reference.renderer = Renderer::kReference;
      return reference;
    }());
    settings["renderer"] = "Blender Cycles " + options.blender_version +
                           " (rgb); lsds reference renderer (Embree 3) (every truth layer)";
    settings["cycles"] = {{"blender_version", options.blender_version},
                          {"samples", options.spp},
                          {"denoise", options.denoise}};
    return settings;
  }
  return {{"renderer", "lsds reference renderer (Embree 3)"},
          {"samples_per_pixel", options.spp},
          {"sampling", "stratified jittered n x n; sample 0 exactly at the pixel centre"},
          {"jitter", options.jitter},
          {"depth", DepthKindName(options.depth_kind)},
          {"zip_level", options.zip_level},
          {"bundle_layout", BundleLayoutName(options.layouts.bundle)},
          {"worldposition_layout", FlatLayoutName(options.layouts.worldposition)},
          {"motion_layout", FlatLayoutName(options.layouts.motion)}};
}

fs::path TruthPartPath(const fs::path& root, int64_t index) {
  return root / kWorkFolder / (FrameStem(index) + ".json");
}

// --renderer cycles: the exported scenes, Cycles' renders and each frame's agreement, in the
// work folder until the collection is assembled.
fs::path CyclesFolder(const fs::path& root) { return root / kWorkFolder / "cycles"; }
fs::path AgreementPartPath(const fs::path& root, int64_t index) {
  return CyclesFolder(root) / (FrameStem(index) + ".agreement.json");
}

// A frame is complete when its truth part parses and every layer file has a
// readable header of the frame's size.
bool FrameComplete(const fs::path& root,
                   const CollectionHeader& header,
                   const PlannedFrame& frame) {
  const fs::path part = TruthPartPath(root, frame.index);
  if (!fs::is_regular_file(part)) return false;
  try {
    const nlohmann::json json = nlohmann::json::parse(ReadFile(part));
    const Frame truth = FrameFromJson(json, part.string(), "");
    for (const LayerInfo& layer : header.layers) {
      const auto it = truth.files.find(layer.name);
      if (it == truth.files.end()) return false;
      const exr::ExrInfo info = exr::ReadExrInfo(root / it->second);
      if (info.width != frame.camera.width || info.height != frame.camera.height ||
          info.deep != layer.deep) {
        return false;
      }
    }
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

// An existing output: --resume needs the same settings, --force deletes only what a generator
// wrote, and without either only an interrupted run is named (to be resumed or replaced).
void CheckExistingOutput(const GenerateOptions& options, const nlohmann::json& settings) {
  const fs::path& root = options.output;
  const fs::path settings_path = root / kWorkFolder / "settings.json";
  if (!fs::exists(root)) return;
  if (options.resume) {
    if (fs::exists(settings_path)) {
      const nlohmann::json previous =
          nlohmann::json::parse(ReadFile(settings_path), nullptr, false);
      if (previous != settings) {
        throw Error("--resume: the existing output was made with other settings (" +
                        previous.dump() + "); use --force to start over",
                    Location(root.string()));
      }
    }
  } else if (options.force) {
    // Only ever delete what a generator wrote: a collection or an interrupted
    // run.
    const bool ours = !fs::is_directory(root) || fs::is_empty(root) || LooksLikeCollection(root) ||
                      fs::exists(root / kWorkFolder);
    if (!ours) {
      throw Error(
          "--force: the output exists and is not a collection; refusing to "
          "delete it",
          Location(root.string()));
    }
    fs::remove_all(root);
  } else if (fs::exists(root / kWorkFolder)) {
    // An interrupted run: --resume keeps its frames, --force deletes them.
    throw Error(
        "the output holds an interrupted run; pass --resume to finish it "
        "(--force deletes its frames and starts over)",
        Location(root.string()));
  } else {
    RefuseToOverwrite(root, false, "output collection");
  }
}

// Resuming a finished collection: its collection.json moves into the work
// folder first (one rename), so that from here until the run ends the
// folder is an interrupted run, never a finished collection describing
// frames that are being rewritten; a failure or a kill leaves it resumable.
void ReopenFinishedCollection(const fs::path& root,
                              const nlohmann::json& settings,
                              const fs::path& finished) {
  std::optional<Provenance> provenance;
  try {
    provenance = CollectionReader(root).header().provenance;
  } catch (const Error&) {
    // An unreadable collection.json is rebuilt from the frames.
  }
  if (provenance) {
    bool same = provenance->seed == settings["seed"].get<uint64_t>();
    for (const auto& [key, value] : settings.items()) {
      if (key != "seed" && provenance->render.value(key, nlohmann::json()) != value) same = false;
    }
    if (!same) {
      throw Error(
          "--resume: the existing collection was made with other settings "
          "(seed " +
              std::to_string(provenance->seed.value_or(0)) + ", " + provenance->render.dump() +
              "); use --force to start over",
          Location((root / kCollectionFile).string()));
    }
  }
  fs::create_directories(finished);
  fs::rename(root / kCollectionFile, finished / kCollectionFile);
}

// The finished collection's frames become truth parts again, so that only frames whose files
// are missing or broken are rendered.
void RestoreTruthParts(const fs::path& root, const fs::path& finished) {
  bool writing = false;  // a failed write is an error; a bad read is not
  try {
    const CollectionReader reader(finished);
    reader.ForEachFrame([&root, &writing](const Frame& frame) {
      const fs::path part = TruthPartPath(root, frame.index);
      if (fs::exists(part)) return;
      writing = true;
      WriteFileAtomic(part, FrameToJson(frame).dump() + "\n");
      writing = false;
    });
  } catch (const Error&) {
    if (writing) throw;
    // An unreadable collection.json is rebuilt from the frames.
  }
}

void PrepareOutput(const GenerateOptions& options, const nlohmann::json& settings) {
  const fs::path& root = options.output;
  const fs::path settings_path = root / kWorkFolder / "settings.json";
  CheckExistingOutput(options, settings);
  // Temporaries of a killed earlier run are removed, never taken for frames.
  if (options.resume) RemoveStaleTemps(root, /*recursive=*/true);
  const fs::path finished = root / kWorkFolder / "finished";
  if (options.resume && LooksLikeCollection(root))
    ReopenFinishedCollection(root, settings, finished);
  fs::create_directories(root / kWorkFolder);
  WriteFileAtomic(settings_path, settings.dump(2) + "\n");
  if (options.resume && LooksLikeCollection(finished)) RestoreTruthParts(root, finished);
}

// The scene state a frame shows (docs/format.md, "Scene state"); the terrain's material when the
// scene has a terrain, and its shape on the frame when the capture changes it (`shape`, else null).
nlohmann::json SceneStateJson(const PlannedEnvironment& environment,
                              bool terrain,
                              const PlannedTerrain* shape) {
  const double el = environment.sun.elevation_deg * M_PI / 180.0,
               az = environment.sun.azimuth_deg * M_PI / 180.0;
  // Azimuth from north (+y), clockwise (towards east, +x), in the ENU world.
  const Eigen::Vector3d to_sun(
      std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
  nlohmann::json visibility = nullptr;
  // Meteorological visibility (Koschmieder, 2 % contrast threshold).
  if (environment.fog_density > 0) visibility = 3.912 / environment.fog_density;
  nlohmann::json state = {
      {"sun",
       {{"azimuth_deg", environment.sun.azimuth_deg},
        {"elevation_deg", environment.sun.elevation_deg},
        {"direction", {to_sun.x(), to_sun.y(), to_sun.z()}},
        {"illuminance_lux", environment.sun.illuminance_lux}}},
      {"sky",
       {{"color",
         {environment.sky.color.x(), environment.sky.color.y(), environment.sky.color.z()}},
        {"luminance_cd_m2", environment.sky.luminance_cd_m2},
        {"cloud_type", environment.sky.cloud_type},
        {"cloud_density", environment.sky.cloud_density}}},
      {"atmosphere", {{"extinction_per_m", environment.fog_density}, {"visibility_m", visibility}}},
      {"skylight_intensity", environment.skylight_intensity}};
  if (terrain) state["terrain_material"] = environment.terrain_material;
  if (shape != nullptr)
    state["terrain_shape"] = {{"perlin_amplitude", shape->perlin_amplitude},
                              {"perlin_frequency", shape->perlin_frequency}};
  return state;
}

// The frame motion of plan frame k is measured against: the previous frame of
// its shot seen by the same camera (the frame before it, or in a rig the same
// camera one time step earlier), if planned.
const PlannedFrame* PreviousInShot(const Plan& plan, size_t k) {
  const PlannedFrame& frame = plan.frames[k];
  const size_t n = plan.rig ? plan.rig->cameras.size() : 1;
  for (size_t back = 1; back <= n && back <= k; ++back) {
    const PlannedFrame& before = plan.frames[k - back];
    if (before.rig_camera != frame.rig_camera) continue;
    const bool next =
        frame.step >= 0 ? before.step + 1 == frame.step : before.index + 1 == frame.index;
    return before.shot == frame.shot && next ? &before : nullptr;
  }
  return nullptr;
}

// Each object's LCAP changes in effect at the frame, as the plan states them.
void RecordObjectChanges(const PlannedFrame& frame, std::vector<ObjectTruth>* objects) {
  for (ObjectTruth& object : *objects) {
    for (const ObjectChange& change : frame.changes) {
      if (change.object != object.name) continue;
      if (object.changes.is_null()) object.changes = nlohmann::json::array();
      object.changes.push_back(ObjectChangeToJson(change));
    }
  }
}

}  // namespace

void GenerateOptions::Check() const {
  if (output.empty()) throw Error("no output folder (-o OUT)");
  if (shard_count < 1 || shard_index < 0 || shard_index >= shard_count) {
    throw Error("--shard " + std::to_string(shard_index) + "/" + std::to_string(shard_count) +
                ": expected I/N with 0 <= I < N");
  }
  if (frames.begin > frames.end) throw Error("--frames A:B needs A <= B");
  if (threads < 0) throw Error("--threads must be >= 0 (0: all cores)");
  if (force && resume) throw Error("--force and --resume exclude each other");
  if (zip_level < 0 || zip_level > 9) throw Error("--zip-level must be in [0, 9]");
  if (denoise && renderer != Renderer::kCycles)
    throw Error("--denoise applies to --renderer cycles only");
  CheckSamplerSettings({spp, jitter, 0});
}

CollectionHeader MakeHeader(const Plan& plan, const GenerateOptions& options) {
  CollectionHeader header;
  header.provenance.generator = "lsds generate";
  header.provenance.generator_version = LSDS_VERSION;
  header.provenance.seed = plan.seed;
  header.provenance.scene_source = plan.scene_source;
  header.provenance.capture_source = plan.capture_source;
  header.provenance.requirements = plan.requirements;
  header.provenance.render = RenderSettingsJson(options);
  if (!plan.post_process.empty()) header.provenance.render["post_process"] = plan.post_process;
  header.classes = plan.classes;
  header.conventions.geo_origin = plan.geo;
  header.rig = plan.rig;
  // Capture Settings `layers` choose the layers written (rgb always); the
  // table keeps the standard order.
  const nlohmann::json& asked = plan.capture_settings.value("layers", nlohmann::json());
  for (const std::string& semantic : StandardLayerSemantics()) {
    const bool wanted = !asked.is_array() || semantic == "rgb" ||
                        std::find(asked.begin(), asked.end(), semantic) != asked.end();
    if (!wanted) continue;
    header.layers.push_back(StandardLayer(semantic, options.depth_kind));
  }
  // Without a depth layer (Capture Settings may leave it out) worldposition and motion stay float.
  ApplyLayerLayouts(options.layouts, &header);
  if (!plan.capture_settings.empty())
    header.provenance.render["capture_settings"] = plan.capture_settings;
  header.metadata = {{kMetadataFile, false, "measured metadata; equal to truth"}};
  // A shard says which run it is part of, so that `lsds merge` can tell a
  // missing or doubled frame; the run itself (one shard) records nothing.
  if (options.shard_count > 1) {
    ShardRecord shard;
    shard.index = options.shard_index;
    shard.count = options.shard_count;
    for (const PlannedFrame& frame : plan.frames) {
      if (!options.frames.Contains(frame.index)) continue;
      if (shard.run_frame_count == 0) shard.run_first_frame = frame.index;
      shard.run_first_frame = std::min(shard.run_first_frame, frame.index);
      shard.run_last_frame = std::max(shard.run_last_frame, frame.index);
      ++shard.run_frame_count;
    }
    header.provenance.shard = shard;
  }
  return header;
}

namespace {

// The stages of GenerateCollection, in order: check the plan and select its frames (nothing
// written yet), prepare the output, render and write the frames (FramePipeline), then assemble
// collection.json from the frames' truth parts.

// The plan's frames the options select (--frames, --shard), as indices into plan.frames.
std::vector<size_t> SelectFrames(const Plan& plan, const GenerateOptions& options) {
  std::vector<size_t> selected;
  for (size_t k = 0; k < plan.frames.size(); ++k) {
    if (options.Selects(plan.frames[k].index)) selected.push_back(k);
  }
  if (selected.empty()) {
    // An empty collection is never a success: say which frames exist.
    const std::string range =
        plan.frames.empty() ? std::string("the plan has no frames")
                            : "the plan has frames " + std::to_string(plan.frames.front().index) +
                                  " to " + std::to_string(plan.frames.back().index);
    throw Error("no frame to render: --frames/--shard select none (" + range + ")");
  }
  return selected;
}

// Before the output is touched: a frame whose film cannot fit in memory is a
// usage error naming the budget, not a 40 GB allocation.
void CheckMemoryBudgets(const Plan& plan,
                        const SceneAssets& assets,
                        const std::vector<size_t>& selected,
                        const GenerateOptions& options) {
  for (size_t k : selected) {
    const PlannedFrame& frame = plan.frames[k];
    CheckImageBudget(frame.camera.width,
                     frame.camera.height,
                     static_cast<int64_t>(Film::BytesPerPixel(options.spp)),
                     1,
                     "frame " + std::to_string(frame.index) + " (camera of the capture, " +
                         std::to_string(options.spp) + " samples per pixel)",
                     "");
  }
  // And a scene whose meshes and BVHs cannot fit (10^5 detailed objects) is the same kind of
  // error, before any output, rather than an out-of-memory halfway through the first frame.
  CheckMemoryBudget(RenderSceneBytes(assets),
                    "the render scene of " + std::to_string(plan.objects.size()) + " objects",
                    "");
}

// The output folder (PrepareOutput: --force, --resume) with one folder per written layer.
void PrepareOutputFolders(const Plan& plan,
                          const GenerateOptions& options,
                          const CollectionHeader& base_header) {
  nlohmann::json settings = RenderSettingsJson(options);
  settings["seed"] = plan.seed;
  if (!plan.capture_settings.empty()) settings["capture_settings"] = plan.capture_settings;
  PrepareOutput(options, settings);
  for (const LayerInfo& layer : base_header.layers) {
    fs::create_directories(options.output / layer.name);
  }
}

// --renderer cycles: what Blender rendered (in the work folder), and per frame index the
// exported nodes its object index pass numbers.
struct CyclesStage {
  fs::path renders;
  std::map<int64_t, std::vector<ExportedNode>> nodes;
  std::unique_ptr<CyclesRun> blender;  // null when every frame was kept (--resume)
};

// Exports the frames still to render (all selected ones, or with --resume those not complete)
// and starts Blender Cycles on them; lsds renders the same frames meanwhile and takes each one's
// Cycles passes as they appear (docs/generator.md, "Blender Cycles").
CyclesStage StartBlender(const Plan& plan,
                         const SceneAssets& assets,
                         const std::vector<size_t>& selected,
                         const GenerateOptions& options,
                         const CollectionHeader& header,
                         GenerateSummary* summary) {
  CyclesStage stage;
  const fs::path folder = CyclesFolder(options.output);
  const fs::path scenes = folder / "scene";
  stage.renders = folder / "render";
  fs::create_directories(scenes);
  fs::create_directories(stage.renders);
  const Clock::time_point t0 = Clock::now();
  const SceneExporter exporter(plan, assets, scenes);
  exporter.WriteGround();
  std::vector<int64_t> frames;
  for (size_t k : selected) {
    const PlannedFrame& frame = plan.frames[k];
    if (options.resume && FrameComplete(options.output, header, frame)) continue;
    stage.nodes[frame.index] = SceneExporter::Nodes(exporter.WriteFrame(frame));
    frames.push_back(frame.index);
  }
  exporter.WriteIndex(frames);
  summary->export_seconds = Seconds(t0);
  if (frames.empty()) return stage;
  stage.blender = std::make_unique<CyclesRun>(
      options.blender,
      scenes,
      stage.renders,
      frames,
      CyclesRenderOptions{options.spp, options.threads, options.denoise},
      folder / "blender.log");
  return stage;
}

// The view motion is measured against (PreviousInShot), with the world and scene it is seen
// in; `view` points into this struct, which therefore stays where it was built.
struct PreviousFrame {
  PreviousView view;
  std::optional<WorldState> world;
  std::unique_ptr<RenderScene> built;  // when neither live scene shows that world
};

// Renders the selected frames and writes each one's layers and truth part. Two films take
// turns: one renders while the other is written on a task, and each is reused (RenderFrame)
// instead of allocated per frame. Scenes are kept per world state: the current one, the one
// before (often the previous frame's), and the one before that is recycled in place.
class FramePipeline {
 public:
  FramePipeline(const Plan& plan,
                const GenerateOptions& options,
                const SceneAssets& assets,
                const CollectionHeader& base_header,
                CyclesStage* cycles,
                GenerateSummary* summary)
      : plan_(plan),
        options_(options),
        assets_(assets),
        base_header_(base_header),
        root_(options.output),
        summary_(*summary),
        cycles_(cycles),
        terrain_shape_changes_(TerrainShapeChanges(plan)) {
    render_.sampler = {options.spp, options.jitter, plan.seed};
    render_.depth_kind = options.depth_kind;
    // Capture Settings `layers`: no work for a layer that is not written.
    render_.bundle = base_header.FindLayerBySemantic("bundle") != nullptr;
    render_.motion = base_header.FindLayerBySemantic("motion") != nullptr;
    // --renderer cycles: Blender makes the rgb, lsds casts only what the truth needs.
    render_.shade_rgb = cycles == nullptr;
  }

  void Run(const std::vector<size_t>& selected) {
    std::optional<Progress> progress;
    if (options_.progress) progress.emplace("generate", static_cast<int64_t>(selected.size()));
    // A failure while a write runs must not leave the task group unwaited.
    try {
      for (size_t k : selected) {
        const PlannedFrame& frame = plan_.frames[k];
        if (options_.resume && FrameComplete(root_, base_header_, frame)) {
          ++summary_.frames_skipped;
          if (progress) progress->Add();
          continue;
        }
        RenderAndQueue(k);
        if (progress) progress->Add();
      }
    } catch (...) {
      try {
        writer_.wait();
      } catch (...) {
      }
      throw;
    }
    writer_.wait();
  }

  // summary.steady_seconds_per_frame: the time the pipeline was full, per frame.
  double SteadySecondsPerFrame() const {
    if (summary_.frames_rendered < 2) return 0;
    return std::chrono::duration<double>(last_overlap_end_ - first_overlap_start_).count() /
           static_cast<double>(summary_.frames_rendered - 1);
  }

 private:
  // Plan frame k: render it and its truth, then queue its write once the last write ended.
  void RenderAndQueue(size_t k) {
    const PlannedFrame& frame = plan_.frames[k];
    const Clock::time_point t0 = Clock::now();
    UpdateScene(WorldAt(plan_, frame));
    PreviousFrame previous;
    FindPrevious(k, &previous);
    const PlannedEnvironment environment = EnvironmentAt(plan_, frame);
    const Sky sky(plan_, environment);    // LCAP may change it per frame
    Film& rendered = films_[rendering_];  // its last write ended (writer_.wait below)
    RenderFrame(*scene_, sky, frame, previous.view, render_, &rendered);
    if (cycles_ != nullptr) UseCycles(frame, &rendered);
    // The camera's exposure: photometric radiance (lsds's or Cycles') to the sensor's scale.
    const FrameExposure exposure = MeterExposure(plan_.exposure, rendered);
    ApplyExposure(exposure, &rendered);
    // LCAP post-process materials: RGB only, after the truth is final.
    const std::optional<double> focused =
        ApplyPostProcess(plan_.post_process, plan_.seed, frame, plan_.exposure, &rendered);
    uint64_t rays = rendered.rays;
    std::shared_ptr<Frame> truth = MakeTruth(frame, rendered, exposure, &rays);
    if (focused) truth->exposure["focus_distance_m"] = *focused;
    summary_.rays += rays;
    summary_.render_seconds += Seconds(t0);

    // Encode this frame while the next one renders: at most two films live.
    writer_.wait();  // rethrows a failed write
    (summary_.frames_rendered == 0 ? first_overlap_start_ : last_overlap_end_) = Clock::now();
    QueueWrite(rendered, truth, MotionReference(previous.view));
    rendering_ = 1 - rendering_;
    ++summary_.frames_rendered;
  }

  // --renderer cycles: Cycles' passes checked against the film's truth, then Cycles' radiance as
  // the rgb (in lsds's photometric units; the exposure meters it as it would lsds's). The
  // agreement part precedes the truth part.
  void UseCycles(const PlannedFrame& frame, Film* film) {
    cycles_->blender->WaitForFrame(frame.index);
    const CyclesAgreement agreement =
        CompareWithCycles(CyclesRgbPath(cycles_->renders, frame.index),
                          *film,
                          cycles_->nodes.at(frame.index),
                          frame.camera,
                          render_.depth_kind,
                          frame.index);
    UseCyclesRgb(CyclesRgbPath(cycles_->renders, frame.index), film);
    WriteFileAtomic(AgreementPartPath(root_, frame.index),
                    AgreementToJson(agreement).dump() + "\n");
    summary_.cycles_agreement.push_back(agreement);
  }

  // One scene per world state. The scene two world states back is updated in place: its
  // objects that did not change keep their BVHs; those of the state before are shared, not
  // rebuilt.
  void UpdateScene(const WorldState& world) {
    if (scene_ && scene_->world() == world) return;
    std::unique_ptr<RenderScene> recycled = std::move(previous_scene_);
    previous_scene_ = std::move(scene_);
    if (recycled) {
      recycled->Update(device_, assets_, world, previous_scene_.get());
      scene_ = std::move(recycled);
    } else {
      scene_ = std::make_unique<RenderScene>(device_, plan_, assets_, world, previous_scene_.get());
    }
  }

  // Motion is measured against the previous frame of the same shot, seen
  // in that frame's world (for moved objects and disocclusions). No motion layer: no
  // previous view to build.
  void FindPrevious(size_t k, PreviousFrame* previous) {
    const PlannedFrame* before = render_.motion ? PreviousInShot(plan_, k) : nullptr;
    if (before == nullptr) return;
    previous->view.frame = before;
    previous->world = WorldAt(plan_, *before);
    previous->view.world = &*previous->world;
    if (scene_->world() == *previous->world) {
      previous->view.scene = scene_.get();
    } else if (previous_scene_ && previous_scene_->world() == *previous->world) {
      previous->view.scene = previous_scene_.get();
    } else {
      previous->built =
          std::make_unique<RenderScene>(device_, plan_, assets_, *previous->world, scene_.get());
      previous->view.scene = previous->built.get();
    }
  }

  // The frame's truth from what was rendered; adds the truth rays to `rays`.
  std::shared_ptr<Frame> MakeTruth(const PlannedFrame& frame,
                                   const Film& film,
                                   const FrameExposure& exposure,
                                   uint64_t* rays) const {
    auto truth = std::make_shared<Frame>();
    truth->index = frame.index;
    truth->time = frame.time;
    truth->sequence = frame.sequence;
    truth->shot = frame.shot;
    truth->camera_velocity = frame.camera_velocity;
    truth->rig_camera = frame.rig_camera;
    if (frame.step >= 0) truth->step = frame.step;
    const PlannedTerrain terrain = TerrainAt(plan_, frame);
    truth->scene = SceneStateJson(EnvironmentAt(plan_, frame),
                                  plan_.terrain.present,
                                  terrain_shape_changes_ ? &terrain : nullptr);
    truth->exposure = ExposureJson(exposure);
    truth->camera.intrinsics = frame.camera;
    SetCamFromWorld(frame.cam_from_world, &truth->camera);
    truth->objects =
        ComputeObjectTruth(*scene_, frame, film, EnvironmentAt(plan_, frame).fog_density, rays);
    RecordObjectChanges(frame, &truth->objects);
    // The final truth is what was rendered: judge the frame's requirements
    // on it.
    if (frame.requirements)
      truth->requirements =
          AchievedRecord(*frame.requirements, MeasureTruth(plan_, frame, truth->objects));
    return truth;
  }

  // The camera motion was measured against, for the residual motion layout.
  std::optional<FrameImages::MotionReference> MotionReference(const PreviousView& previous) const {
    std::optional<FrameImages::MotionReference> motion;
    if (render_.motion) {
      motion.emplace();
      if (previous.frame != nullptr) {
        CameraTruth& camera = motion->previous_camera.emplace();
        camera.intrinsics = previous.frame->camera;
        SetCamFromWorld(previous.frame->cam_from_world, &camera);
      }
    }
    return motion;
  }

  void QueueWrite(const Film& rendered,
                  const std::shared_ptr<Frame>& truth,
                  const std::optional<FrameImages::MotionReference>& motion) {
    const Film* film = &rendered;
    const BundleSampling sampling{render_.sampler, truth->index, std::nullopt};
    writer_.run([this, film, truth, sampling, motion]() {
      const Clock::time_point w0 = Clock::now();
      truth->files = WriteFrameLayers(root_,
                                      base_header_,
                                      truth->index,
                                      truth->camera,
                                      {&film->flat, &film->bundle, sampling, motion},
                                      truth->rig_camera);
      // The truth part comes last: its presence marks the frame complete.
      WriteFileAtomic(TruthPartPath(root_, truth->index), FrameToJson(*truth).dump() + "\n");
      std::lock_guard<std::mutex> lock(write_mutex_);
      summary_.write_seconds += Seconds(w0);
    });
  }

  const Plan& plan_;
  const GenerateOptions& options_;
  const SceneAssets& assets_;
  const CollectionHeader& base_header_;
  const fs::path& root_;
  GenerateSummary& summary_;
  CyclesStage* cycles_;         // null: the reference renderer's rgb
  bool terrain_shape_changes_;  // some frame changes the terrain's shape: every frame records it
  RenderSettings render_;
  EmbreeDevice device_;
  std::unique_ptr<RenderScene> scene_, previous_scene_;
  std::array<Film, 2> films_;
  size_t rendering_ = 0;
  tbb::task_group writer_;
  std::mutex write_mutex_;
  // Where the pipeline is full: summary.steady_seconds_per_frame.
  Clock::time_point first_overlap_start_, last_overlap_end_;
};

// Assemble collection.json and metadata.json from the truth parts, in frame
// order.
void AssembleCollection(const Plan& plan,
                        const GenerateOptions& options,
                        const CollectionHeader& base_header,
                        const std::vector<size_t>& selected,
                        GenerateSummary* summary) {
  const fs::path& root = options.output;
  CollectionHeader header = base_header;
  header.frame_count = static_cast<int64_t>(selected.size());
  if (options.renderer == Renderer::kCycles) {
    // Frames kept by --resume from a finished collection have no part: the figures cover the
    // frames Cycles rendered.
    std::vector<CyclesAgreement> agreements;
    for (size_t k : selected) {
      const fs::path part = AgreementPartPath(root, plan.frames[k].index);
      if (fs::exists(part))
        agreements.push_back(AgreementFromJson(nlohmann::json::parse(ReadFile(part))));
    }
    header.provenance.render["cycles_agreement"] = AgreementSummaryJson(agreements);
  }
  CollectionBuilder builder(root, header);
  for (size_t k : selected) {
    const fs::path part = TruthPartPath(root, plan.frames[k].index);
    const Frame truth = FrameFromJson(nlohmann::json::parse(ReadFile(part)), part.string(), "");
    AddRequirementSummary(plan, truth, &summary->requirements);
    MetadataFrame metadata = TruthMetadata(truth, header.conventions.world);
    AddSurveyMetadata(plan, plan.frames[k], &metadata);
    builder.Append(truth, metadata);
  }
  // A folder with collection.json never holds a work folder, even if the run
  // is killed here: the work folder is renamed to a temporary name before
  // collection.json appears (a kill leaves a stale temporary, which the next
  // write removes). A kill between the two leaves neither, and --resume
  // renders the frames again.
  const fs::path retired = TempPathBeside(root / kWorkFolder);
  fs::rename(root / kWorkFolder, retired);
  builder.Commit();
  fs::remove_all(retired);
}

}  // namespace

GenerateSummary GenerateCollection(const Plan& plan, const GenerateOptions& given) {
  const Clock::time_point start = Clock::now();
  given.Check();
  GenerateOptions options = given;
  if (options.renderer == Renderer::kCycles) {
    // Before any output: Blender is there, and every object gets an object index pass value.
    if (plan.objects.empty() ? false : ObjectPassIndex(plan.objects.size() - 1) > kMaxPassIndex)
      throw Error("--renderer cycles: " + std::to_string(plan.objects.size()) +
                  " objects; Blender's object index pass numbers at most " +
                  std::to_string(kMaxPassIndex - ObjectPassIndex(0) + 1));
    options.blender = FindBlender(given.blender).string();
    options.blender_version = BlenderVersion(options.blender);
  }
  const ThreadLimit thread_limit(options.threads);
  // OpenEXR's thread pool compresses the chunks of one file in parallel: the
  // deep bundle, the longest file, no longer encodes on one core
  // (bench_exr_compression).
  exr::SetEncoderSettings(options.zip_level, options.threads);
  // Validate the whole plan before touching the output.
  const SceneAssets assets = BuildSceneAssets(plan);
  const Sky plan_sky(plan);  // throws for a bad sky before any output
  for (const PlannedFrame& f : plan.frames)
    if (f.environment) Sky(plan, *f.environment);
  const std::vector<size_t> selected = SelectFrames(plan, options);
  CheckMemoryBudgets(plan, assets, selected, options);
  // The Embree plug-in (every renderer's truth is lsds's ray casts): one that cannot be loaded
  // is an error before any output, not a half-made collection.
  Embree();
  const CollectionHeader base_header = MakeHeader(plan, options);
  PrepareOutputFolders(plan, options, base_header);

  GenerateSummary summary;
  std::optional<CyclesStage> cycles;
  if (options.renderer == Renderer::kCycles)
    cycles = StartBlender(plan, assets, selected, options, base_header, &summary);
  FramePipeline pipeline(plan, options, assets, base_header, cycles ? &*cycles : nullptr, &summary);
  pipeline.Run(selected);
  if (cycles && cycles->blender) summary.cycles_seconds = cycles->blender->Finish();

  const Clock::time_point t0 = Clock::now();
  AssembleCollection(plan, options, base_header, selected, &summary);
  summary.write_seconds += Seconds(t0);
  summary.total_seconds = Seconds(start);
  summary.steady_seconds_per_frame = pipeline.SteadySecondsPerFrame();
  return summary;
}

}  // namespace lsds::gen
