#include "bundles/bundle_run.h"

#include <algorithm>
#include <fstream>
#include <memory>
#include <optional>
#include <set>

#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include "bundles/derived_layers.h"
#include "bundles/mixed_map.h"
#include "bundles/stats_json.h"
#include "libs/collection/collection_guard.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_stream.h"
#include "libs/exr/deep_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/check.h"
#include "libs/util/error.h"
#include "libs/util/folder_lock.h"
#include "libs/util/output_guard.h"
#include "libs/util/progress.h"
#include "libs/util/text_check.h"

namespace lsds::bundle {

namespace fs = std::filesystem;

const LayerInfo& FindBundleLayer(const CollectionHeader& header,
                                 const std::string& collection_file) {
  const LayerInfo* layer = header.FindLayerBySemantic("bundle");
  if (layer == nullptr) {
    throw Error(
        "the collection has no bundle layer (a deep layer with semantic "
        "\"bundle\": several samples "
        "per pixel); produce one with `lsds generate --spp N` (N > 1 samples "
        "per pixel)",
        Location(collection_file, "/layers"));
  }
  if (!layer->deep) {
    throw Error("the bundle layer '" + layer->name + "' is not deep",
                Location(collection_file, "/layers"));
  }
  for (const char* channel : {"instanceid", "classid", "Z"}) {
    if (layer->FindChannel(channel) == nullptr) {
      throw Error("the bundle layer '" + layer->name + "' has no channel '" + channel + "'",
                  Location(collection_file, "/layers"));
    }
  }
  return *layer;
}

namespace {

struct Task {
  Frame frame;
  bool analyse = false;
  bool picture = false;
  std::optional<BundleStats> stats;
};

// The stages of RunBundles, in order: check the outputs and plan the derived layers (nothing
// written yet), analyse the frames in batches (BatchRunner), commit the layers and then the
// table that registers them, and write the statistics from the per-frame spool.

// No output may be, contain or lie inside an input (libs/util/output_guard.h):
// the statistics and the picture go outside the collection; derived layers
// go into their own folders only.
void CheckOutputFiles(const fs::path& root, const RunOptions& options) {
  OutputGuard read_guard("lsds bundles");
  GuardCollection(&read_guard, root, CollectionAccess::kReadOnly);
  read_guard.CheckOutput(options.output, "-o");
  read_guard.CheckOutput(options.mixed_map, "--mixed-map");
  if (!options.output.empty()) RefuseToOverwrite(options.output, options.force, "statistics file");
  if (!options.mixed_map.empty()) RefuseToOverwrite(options.mixed_map, options.force, "picture");
}

// The derived layers to write: the new header that registers them and one temporary folder
// per requested layer, in the order of options.write_layers.
struct DerivedLayersPlan {
  CollectionHeader new_header;
  std::vector<std::unique_ptr<AtomicDirectory>> folders;
};

// New layers: refuse to touch existing ones, except earlier derived layers
// with --force.
DerivedLayersPlan PlanDerivedLayers(const fs::path& root,
                                    const RunOptions& options,
                                    const CollectionHeader& header,
                                    const std::string& collection_file,
                                    bool all_frames) {
  DerivedLayersPlan plan{header, {}};
  std::set<std::string> replaceable;  // derived layers of an earlier run
  for (const LayerInfo& layer : header.layers) {
    if (layer.semantic == "derived") replaceable.insert(layer.name);
  }
  // Folders an interrupted run renamed into place before it registered them.
  std::set<std::string> unregistered;
  for (const std::string& name : options.write_layers) {
    if (!header.FindLayer(name) && IsUnregisteredDerivedFolder(root / name, name)) {
      unregistered.insert(name);
      if (options.force) replaceable.insert(name);
    }
  }
  OutputGuard layer_guard("lsds bundles");
  GuardCollection(&layer_guard, root, CollectionAccess::kAddsOutputs, replaceable);
  for (const std::string& name : options.write_layers) {
    const LayerInfo layer = DerivedLayer(name, all_frames);
    auto it = std::find_if(plan.new_header.layers.begin(),
                           plan.new_header.layers.end(),
                           [&](const LayerInfo& l) { return l.name == name; });
    if (it != plan.new_header.layers.end()) {
      if (it->semantic != "derived") {
        throw Error("the collection already has a layer '" + name + "' (semantic \"" +
                        it->semantic + "\"); existing layers are never modified",
                    Location(collection_file, "/layers"));
      }
      if (!options.force) {
        throw Error("the collection already has a derived layer '" + name +
                        "' (written by an earlier run); use --force to replace it",
                    Location(collection_file, "/layers"));
      }
      *it = layer;
    } else {
      std::error_code ec;
      if (unregistered.count(name) && !options.force) {
        throw Error("the collection holds a '" + name +
                        "' folder left by an interrupted `lsds bundles --write-layers` run "
                        "(not registered in collection.json); use --force to replace it",
                    Location((root / name).string()));
      }
      if (!unregistered.count(name) && fs::exists(root / name, ec)) {
        // --force replaces only what an earlier `lsds bundles` wrote.
        throw Error("the collection holds a '" + name +
                        "' that is not one of its derived layers; lsds never "
                        "replaces it, even with --force",
                    Location((root / name).string()));
      }
      plan.new_header.layers.push_back(layer);
    }
    layer_guard.CheckOutput(root / name, "--write-layers");
    plan.folders.push_back(std::make_unique<AtomicDirectory>(root / name, options.force));
  }
  // One folder per requested layer, in order: Process() indexes both alike.
  LSDS_CHECK(plan.folders.size() == options.write_layers.size());
  return plan;
}

// The bundle channels to decode: the normals only when the layer has all three.
std::vector<std::string> ChannelsToRead(const LayerInfo& bundle_layer) {
  std::vector<std::string> channels = {"instanceid", "classid", "Z"};
  if (bundle_layer.FindChannel("NX") && bundle_layer.FindChannel("NY") &&
      bundle_layer.FindChannel("NZ")) {
    channels.insert(channels.end(), {"NX", "NY", "NZ"});
  }
  return channels;
}

// Analyses the frames a batch at a time (decoded in parallel, bounded memory), then, in frame
// order, merges their statistics, spools their records and passes every frame to the writer
// of the new collection.json with its derived layers' files.
class BatchRunner {
 public:
  BatchRunner(const CollectionReader& reader,
              const RunOptions& options,
              const LayerInfo& bundle_layer,
              DerivedLayersPlan* layers,
              std::optional<CollectionWriter>* writer,
              std::optional<AtomicFile>* spool,
              Progress* progress,
              RunResult* result)
      : reader_(reader),
        options_(options),
        bundle_layer_(bundle_layer),
        channels_(ChannelsToRead(bundle_layer)),
        layers_(*layers),
        writer_(*writer),
        spool_(*spool),
        progress_(*progress),
        result_(*result) {}

  void Flush(std::vector<Task>* batch) {
    tbb::parallel_for(size_t{0}, batch->size(), [&](size_t i) {
      if ((*batch)[i].analyse) Process((*batch)[i]);
    });
    for (Task& task : *batch) Record(task);
    batch->clear();
  }

 private:
  // Decodes and analyses one frame, and writes its derived layers and picture.
  void Process(Task& task) {
    const fs::path path = reader_.LayerPath(task.frame, bundle_layer_.name);
    const exr::DeepImage image = reader_.ReadDeepLayer(task.frame, bundle_layer_.name, channels_);
    const bool need_maps = !options_.write_layers.empty() || task.picture;
    PixelMaps maps;
    try {
      task.stats = AnalyzeFrame(image, options_.stats, need_maps ? &maps : nullptr);
    } catch (const Error& e) {
      Location where(path.string());
      where.frame = task.frame.index;
      throw Error(e.message(), where);
    }
    const std::string file_name = path.filename().string();
    for (size_t i = 0; i < options_.write_layers.size(); ++i) {
      WriteDerivedLayer(options_.write_layers[i],
                        maps,
                        image.width(),
                        image.height(),
                        layers_.folders[i]->temp_path() / file_name);
    }
    if (task.picture) WriteMixedMapPng(options_.mixed_map, maps, image.width(), image.height());
    progress_.Add();
  }

  // In frame order: the totals, the spooled record and the frame's entry in the new table.
  void Record(Task& task) {
    if (task.analyse) {
      result_.total.Merge(*task.stats);
      ++result_.frames_analyzed;
      if (spool_) {
        const nlohmann::json record = {
            {"index", task.frame.index},
            {"file", task.frame.files.at(bundle_layer_.name)},
            {"stats", StatsToJson(*task.stats, options_.stats, reader_.header())}};
        spool_->stream() << record.dump() << "\n";
      }
    }
    if (!writer_) return;
    const std::string file_name = fs::path(task.frame.files.count(bundle_layer_.name)
                                               ? task.frame.files.at(bundle_layer_.name)
                                               : std::string())
                                      .filename()
                                      .string();
    for (const std::string& name : options_.write_layers) {
      if (task.analyse) {
        task.frame.files[name] = name + "/" + file_name;
      } else {
        task.frame.files.erase(name);  // a replaced derived layer keeps no stale entry
      }
    }
    writer_->Append(task.frame);
  }

  const CollectionReader& reader_;
  const RunOptions& options_;
  const LayerInfo& bundle_layer_;
  const std::vector<std::string> channels_;
  DerivedLayersPlan& layers_;
  std::optional<CollectionWriter>& writer_;
  std::optional<AtomicFile>& spool_;
  Progress& progress_;
  RunResult& result_;
};

// The statistics file: the run's header and totals, then the spooled per-frame records.
void WriteStatsFile(const fs::path& root,
                    const RunOptions& options,
                    const CollectionHeader& header,
                    const LayerInfo& bundle_layer,
                    int64_t first,
                    int64_t end,
                    const RunResult& result,
                    AtomicFile* spool) {
  spool->stream().flush();
  nlohmann::json top = {{"format", kStatsFormat},
                        {"format_version", kStatsFormatVersion},
                        {"collection", Utf8Escaped(fs::absolute(root).lexically_normal().string())},
                        {"bundle_layer", bundle_layer.name},
                        {"frame_range", {{"first", first}, {"end", end}}},
                        {"options", OptionsToJson(options.stats)},
                        {"layers_written", options.write_layers},
                        {"summary", StatsToJson(result.total, options.stats, header)},
                        {"objects", ObjectsToJson(result.total)}};
  JsonArrayWriter out(options.output, top, "frames");
  std::ifstream in(spool->temp_path());
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) out.Append(nlohmann::json::parse(line));
  }
  out.Commit();
}

}  // namespace

RunResult RunBundles(const fs::path& root, const RunOptions& options) {
  // Writers of one collection take turns, and the header is read under the
  // lock, so that no other writer's change to collection.json is lost.
  std::optional<FolderLock> lock;
  if (!options.write_layers.empty()) {
    CheckCollectionFolder(root);
    lock.emplace(root, "lsds bundles");
  }
  const CollectionReader reader(root);
  const std::string collection_file = reader.collection_path().string();
  const CollectionHeader& header = reader.header();
  const LayerInfo& bundle_layer = FindBundleLayer(header, collection_file);
  const int64_t count = static_cast<int64_t>(reader.frames_in_file());
  CheckOutputFiles(root, options);
  const bool all_frames = options.frames.all();
  DerivedLayersPlan layers = PlanDerivedLayers(root, options, header, collection_file, all_frames);
  std::optional<CollectionWriter> writer;
  if (!options.write_layers.empty()) writer.emplace(root, layers.new_header);

  // Per-frame records go to a spool beside the output, so that memory does not
  // grow with frames.
  std::optional<AtomicFile> spool;
  if (!options.output.empty()) spool.emplace(TempPathBeside(options.output));

  RunResult result{BundleStats(options.stats), 0, bundle_layer.name};
  const size_t batch_size =
      options.batch > 0 ? options.batch
                        : static_cast<size_t>(std::max(1, tbb::info::default_concurrency()));
  // Indices are unique (docs/format.md): a range holds at most end - begin frames.
  const int64_t at_most = options.frames.end - std::max<int64_t>(0, options.frames.begin);
  Progress progress("bundles", std::min(count, at_most));
  BatchRunner runner(reader, options, bundle_layer, &layers, &writer, &spool, &progress, &result);
  std::vector<Task> batch;
  batch.reserve(batch_size);
  bool first_analysed = true;
  int64_t index_end = 0;  // one past the collection's last frame index
  reader.ForEachFrame([&](const Frame& frame) {
    index_end = std::max(index_end, frame.index + 1);
    const bool analyse = options.frames.Contains(frame.index);
    const bool picture = analyse && first_analysed && !options.mixed_map.empty();
    if (analyse) first_analysed = false;
    if (!analyse && !writer) return;
    batch.push_back({frame, analyse, picture, std::nullopt});
    if (batch.size() == batch_size) runner.Flush(&batch);
  });
  runner.Flush(&batch);

  // Layers first, then the table that registers them: a failure never leaves a
  // table pointing at missing files.
  for (auto& folder : layers.folders) folder->Commit();
  if (writer) writer->Commit();

  if (spool) {
    const int64_t first = options.frames.begin;
    const int64_t end = options.frames.bounded() ? options.frames.end : index_end;
    WriteStatsFile(root, options, header, bundle_layer, first, end, result, &*spool);
  }
  return result;
}

}  // namespace lsds::bundle
