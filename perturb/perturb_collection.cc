#include "perturb/perturb_collection.h"

#include <fstream>
#include <memory>
#include <optional>
#include <vector>

#include "libs/collection/collection_guard.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/json_io.h"
#include "libs/collection/schema.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/folder_lock.h"
#include "libs/util/output_guard.h"
#include "libs/util/progress.h"
#include "perturb/json_array_scan.h"
#include "perturb/metadata_perturber.h"

namespace lsds::noise {

namespace fs = std::filesystem;

std::string DefaultOutputName(uint64_t seed) {
  return "metadata.perturbed-" + std::to_string(seed) + ".json";
}

namespace {

// `path` relative to `root` when it lies inside it ("metadata.x.json",
// "sub/x.json"), else "".
std::string RelativeInside(const fs::path& path, const fs::path& root) {
  const fs::path relative =
      fs::weakly_canonical(path).lexically_relative(fs::weakly_canonical(root));
  if (relative.empty()) return "";
  const std::string first = relative.begin()->string();
  if (first == ".." || first == ".") return "";
  return relative.generic_string();
}

const MetadataVariant* FindTruthVariant(const CollectionHeader& header) {
  for (const MetadataVariant& variant : header.metadata) {
    if (!variant.perturbed) return &variant;
  }
  return nullptr;
}

// Streams the report file: {"format", ..., "frames": [...], "summary": {...}};
// the summary goes last because it is known only at the end.
class ReportWriter {
 public:
  ReportWriter(const fs::path& path, const nlohmann::json& head) : file_(path) {
    std::string text = head.dump(2);
    text.erase(text.find_last_of('}'));
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    file_.stream() << text << ",\n  \"frames\": [";
  }
  void Append(const FrameDisplacement& frame) {
    file_.stream() << (count_++ == 0 ? "\n    " : ",\n    ") << frame.ToJson().dump();
  }
  void Finish(const nlohmann::json& summary) {
    std::string text = summary.dump(2);
    // Indent the summary object by two spaces to sit inside the root object.
    std::string indented;
    for (char c : text) {
      indented += c;
      if (c == '\n') indented += "  ";
    }
    file_.stream() << (count_ == 0 ? "],\n" : "\n  ],\n") << "  \"summary\": " << indented
                   << "\n}\n";
  }
  void Check() { file_.Check(); }
  void Commit() { file_.Commit(); }

 private:
  AtomicFile file_;
  size_t count_ = 0;
};

}  // namespace

// The realized error of each frame. In a rig collection the cameras of one
// time step ride one platform: one error is drawn per step (frames of a step
// are consecutive, index = step * cameras + camera) and every camera of the
// step gets it, as one GNSS/INS fix would.
class FrameErrors {
 public:
  FrameErrors(MetadataPerturber* perturber, const CollectionHeader& header)
      : perturber_(perturber),
        cameras_(header.rig ? static_cast<int64_t>(header.rig->cameras.size()) : 1) {}
  RealizedError Next(int64_t frame_index, double time) {
    if (cameras_ == 1) return perturber_->NextError(frame_index, time);
    const int64_t step = frame_index / cameras_;
    if (!last_ || last_->first != step) last_.emplace(step, perturber_->NextError(step, time));
    return last_->second;
  }

 private:
  MetadataPerturber* perturber_;
  int64_t cameras_;
  std::optional<std::pair<int64_t, RealizedError>> last_;
};

namespace {

// The stages of PerturbCollection, in order: read and check the collection's header, check
// the outputs (nothing written yet), write the perturbed variant (one pass over the truth
// metadata), rewrite collection.json and measure the report (one pass over its frames), then
// commit every file. Each file stays temporary until all are complete.

// The output and the report: refuse to overwrite the inputs ever, and anything else without
// --force. Fills result.output, result.report and result.registered_as.
void CheckOutputs(const PerturbOptions& options,
                  const fs::path& planned_output,
                  PerturbResult* result) {
  const fs::path& root = options.collection;
  std::error_code ec;
  result->output = planned_output;
  const fs::path output_canonical = fs::weakly_canonical(result->output);
  // The variant may go into the collection (where it is registered), but never
  // onto collection.json, the truth metadata or into a layer folder.
  OutputGuard guard("lsds perturb-metadata");
  guard.AddInput(result->source, "truth metadata");
  GuardCollection(&guard, root, CollectionAccess::kAddsOutputs);
  guard.CheckOutput(result->output, "-o");
  if (!fs::is_directory(fs::absolute(result->output).parent_path(), ec)) {
    throw Error("the output's folder does not exist", Location(result->output.string()));
  }
  if (fs::is_directory(result->output, ec)) {
    throw Error("the output is a folder; -o takes a file name", Location(result->output.string()));
  }
  RefuseToOverwrite(result->output, options.force, "output metadata");
  if (options.report) {
    fs::path report = options.report_path;
    if (report.empty()) {
      report = result->output;
      report.replace_extension(".report.json");
    }
    if (fs::weakly_canonical(report) == output_canonical) {
      throw Error("the report and the output metadata are the same file",
                  Location(report.string()));
    }
    guard.CheckOutput(report, "--report");
    if (fs::is_directory(report, ec)) {
      throw Error("the report is a folder; --report takes a file name", Location(report.string()));
    }
    RefuseToOverwrite(report, options.force, "report");
    result->report = report;
  }
  result->registered_as = RelativeInside(result->output, root);
}

// One pass over the truth metadata: each frame parsed, checked, perturbed and
// written to a temporary file, the statistics accumulated; the output is then
// the header (which states the statistics) followed by those frames.
// Returns the output, complete but not committed; fills result.summary and result.frames.
std::unique_ptr<AtomicFile> WritePerturbedVariant(const PerturbOptions& options,
                                                  const CollectionHeader& header,
                                                  const MetadataVariant& truth_variant,
                                                  PerturbResult* result) {
  const WorldFrame& world = header.conventions.world;
  const std::string source_file = result->source.string();
  const JsonSchema& frame_schema = JsonSchema::Get("metadata.schema.json", "frame");
  AtomicFile frames_file(fs::path(result->output).concat(".frames"));
  ErrorStatistics statistics;
  MetadataPerturber perturber(options.spec, world);
  FrameErrors errors(&perturber, header);
  std::unique_ptr<Progress> progress;
  if (options.progress)
    progress = std::make_unique<Progress>("perturb-metadata", header.frame_count);
  std::ostream& frames_out = frames_file.stream();
  const ArrayScanResult metadata_scan = ScanJsonArrayMember(
      result->source, "frames", {nullptr, [&](std::string_view text, size_t index) {
                                   const std::string pointer = "/frames/" + std::to_string(index);
                                   const nlohmann::json json =
                                       ParseElement(text, result->source, pointer);
                                   frame_schema.ValidateOrThrow(json, source_file, pointer);
                                   const MetadataFrame truth =
                                       MetadataFrameFromJson(json, source_file, pointer);
                                   const RealizedError error = errors.Next(truth.index, truth.time);
                                   statistics.Add(error);
                                   frames_out
                                       << (index == 0 ? "\n    " : ",\n    ")
                                       << MetadataFrameToJson(perturber.Apply(truth, error)).dump();
                                   if (progress) progress->Add();
                                 }});
  progress.reset();
  JsonSchema::Get("metadata.schema.json").ValidateOrThrow(metadata_scan.header, source_file);
  const MetadataHeader truth_header = MetadataHeaderFromJson(metadata_scan.header, source_file);
  if (truth_header.perturbed) {
    throw Error("the metadata registered as truth is itself perturbed",
                Location(source_file, "/perturbed"));
  }
  if (truth_header.frame_count != static_cast<int64_t>(metadata_scan.elements)) {
    throw Error("frame_count is " + std::to_string(truth_header.frame_count) +
                    " but the file has " + std::to_string(metadata_scan.elements) + " frames",
                Location(source_file, "/frame_count"));
  }
  result->summary = statistics.ToJson();
  result->frames = statistics.count();

  MetadataHeader out_header;
  out_header.format_version = truth_header.format_version;
  out_header.perturbed = true;
  out_header.noise = NoiseRecord{
      NoiseModelName(options.spec.model), options.spec.ParametersJson(world), options.spec.seed};
  out_header.source = truth_variant.file;
  out_header.frame_count = truth_header.frame_count;
  nlohmann::json out_header_json = MetadataHeaderToJson(out_header);
  out_header_json["summary"] = result->summary;
  auto output = std::make_unique<AtomicFile>(result->output);
  output->stream() << ArrayFileHead(out_header_json, "frames");
  frames_file.Check();  // the scratch frames were all written
  if (result->frames > 0) {
    std::ifstream frames_in(frames_file.temp_path(), std::ios::binary);
    output->stream() << frames_in.rdbuf();
  }
  output->stream() << (result->frames == 0 ? "]\n}\n" : "\n  ]\n}\n");
  return output;
}

// collection.json's new header, with the variant registered (replacing an entry of the same
// file), written up to its frames; nullptr when the variant lies outside the collection.
std::unique_ptr<AtomicFile> StartRegistry(const PerturbOptions& options,
                                          const PerturbResult& result,
                                          nlohmann::json* collection_json) {
  if (result.registered_as.empty()) return nullptr;
  nlohmann::json entry = {{"file", result.registered_as},
                          {"perturbed", true},
                          {"description", options.spec.Describe()}};
  nlohmann::json& variants = (*collection_json)["metadata"];
  bool replaced = false;
  for (nlohmann::json& variant : variants) {
    if (variant.value("file", "") == result.registered_as) {
      variant = entry;
      replaced = true;
    }
  }
  if (!replaced) variants.push_back(entry);
  auto registry = std::make_unique<AtomicFile>(options.collection / kCollectionFile);
  registry->stream() << ArrayFileHead(*collection_json, "frames");
  return registry;
}

// The report's writer, its head written; nullptr without --report.
std::unique_ptr<ReportWriter> StartReport(const PerturbOptions& options,
                                          const PerturbResult& result) {
  if (!result.report) return nullptr;
  return std::make_unique<ReportWriter>(
      *result.report,
      nlohmann::json{{"format", "lsds-perturb-report"},
                     {"metadata", result.output.filename().string()},
                     {"model", NoiseModelName(options.spec.model)},
                     {"seed", options.spec.seed}});
}

// Pass over collection.json: the frames' bytes copied verbatim after the registry's new
// header, and each frame's displacement measured for the report, when either is written.
// Returns the displacement summary.
DisplacementSummary CopyFramesAndMeasure(const PerturbOptions& options,
                                         const CollectionHeader& header,
                                         AtomicFile* registry,
                                         ReportWriter* report) {
  const fs::path collection_path = options.collection / kCollectionFile;
  const std::string collection_file = collection_path.string();
  const WorldFrame& world = header.conventions.world;
  DisplacementSummary displacement;
  MetadataPerturber report_perturber(options.spec, world);
  FrameErrors report_errors(&report_perturber, header);
  if (registry == nullptr && report == nullptr) return displacement;
  ArrayScanCallbacks callbacks;
  if (registry != nullptr) {
    std::ostream& out = registry->stream();
    callbacks.on_raw = [&out](std::string_view bytes) {
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    };
  }
  if (report != nullptr) {
    callbacks.on_element = [&](std::string_view text, size_t index) {
      const std::string pointer = "/frames/" + std::to_string(index);
      const Frame frame =
          FrameFromJson(ParseElement(text, collection_path, pointer), collection_file, pointer);
      // The measured camera, from the truth as metadata.json states it
      // (TruthMetadata) and the same realized error as the output's frame of
      // that index.
      const MetadataFrame truth = TruthMetadata(frame, world);
      const MetadataFrame measured =
          report_perturber.Apply(truth, report_errors.Next(truth.index, truth.time));
      const FrameDisplacement moved = MeasureDisplacement(frame, world, measured);
      displacement.Add(moved);
      report->Append(moved);
    };
  }
  ScanJsonArrayMember(collection_path, "frames", callbacks);
  if (registry != nullptr) registry->stream() << "]\n}\n";
  return displacement;
}

}  // namespace

PerturbResult PerturbCollection(const PerturbOptions& options) {
  options.spec.Validate();
  const fs::path& root = options.collection;
  const fs::path collection_path = root / kCollectionFile;
  const std::string collection_file = collection_path.string();
  CheckCollectionFolder(root);
  // Registering the variant rewrites collection.json: writers of one collection
  // take turns, and the header is read under the lock so that no other
  // writer's registration is lost.
  const fs::path planned_output =
      options.output.empty() ? root / DefaultOutputName(options.spec.seed) : options.output;
  std::optional<FolderLock> lock;
  if (!RelativeInside(planned_output, root).empty()) lock.emplace(root, "lsds perturb-metadata");
  std::error_code ec;
  // The header only (a fast scan, no DOM for the frames), checked as
  // CollectionReader checks it.
  ArrayScanResult collection_scan = ScanJsonArrayMember(collection_path, "frames");
  JsonSchema::Get("collection.schema.json")
      .ValidateOrThrow(collection_scan.header, collection_file);
  const CollectionHeader header = HeaderFromJson(collection_scan.header, collection_file);

  // The truth to perturb: the collection's unperturbed metadata variant.
  const MetadataVariant* truth_variant = FindTruthVariant(header);
  if (truth_variant == nullptr) {
    throw Error(
        "the collection has no truth metadata to perturb (no unperturbed entry "
        "in its "
        "\"metadata\" list)",
        Location(collection_file, "/metadata"));
  }
  PerturbResult result;
  result.source = root / truth_variant->file;
  if (!fs::is_regular_file(result.source, ec)) {
    throw Error("the truth metadata registered in " + collection_file + " does not exist",
                Location(result.source.string()));
  }
  CheckOutputs(options, planned_output, &result);

  std::unique_ptr<AtomicFile> output =
      WritePerturbedVariant(options, header, *truth_variant, &result);
  std::unique_ptr<AtomicFile> registry = StartRegistry(options, result, &collection_scan.header);
  std::unique_ptr<ReportWriter> report = StartReport(options, result);
  const DisplacementSummary displacement =
      CopyFramesAndMeasure(options, header, registry.get(), report.get());

  // Every file is complete and flushed before any is renamed into place: a
  // full disk or a failing report is met while nothing is visible yet.
  if (report) {
    result.report_summary = displacement.ToJson();
    report->Finish(*result.report_summary);
    report->Check();
  }
  output->Check();
  if (registry) registry->Check();
  // Then the report and the variant go into place before collection.json
  // registers the variant, so that a registered variant always has its files;
  // a rename that fails removes the files this run created before it (files
  // replaced with --force keep their new content).
  std::vector<fs::path> created;
  try {
    const auto commit = [&created, &ec](auto& file, const fs::path& path) {
      const bool existed = fs::exists(path, ec);
      file.Commit();
      if (!existed) created.push_back(path);
    };
    if (report) commit(*report, *result.report);
    commit(*output, result.output);
    if (registry) registry->Commit();
  } catch (const Error&) {
    for (const fs::path& path : created) fs::remove(path, ec);
    throw;
  }
  return result;
}

}  // namespace lsds::noise
