#include "libs/noise/perturb_collection.h"

#include <memory>

#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/noise/metadata_perturber.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/progress.h"

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
    while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
      text.pop_back();
    file_.stream() << text << ",\n  \"frames\": [";
  }
  void Append(const FrameDisplacement& frame) {
    file_.stream() << (count_++ == 0 ? "\n    " : ",\n    ")
                   << frame.ToJson().dump();
  }
  void Finish(const nlohmann::json& summary) {
    std::string text = summary.dump(2);
    // Indent the summary object by two spaces to sit inside the root object.
    std::string indented;
    for (char c : text) {
      indented += c;
      if (c == '\n') indented += "  ";
    }
    file_.stream() << (count_ == 0 ? "],\n" : "\n  ],\n")
                   << "  \"summary\": " << indented << "\n}\n";
  }
  void Commit() { file_.Commit(); }

 private:
  AtomicFile file_;
  size_t count_ = 0;
};

}  // namespace

PerturbResult PerturbCollection(const PerturbOptions& options) {
  options.spec.Validate();
  const CollectionReader collection(options.collection);
  const CollectionHeader& header = collection.header();
  const std::string collection_file = collection.collection_path().string();
  const WorldFrame& world = header.conventions.world;

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
  result.source = collection.root() / truth_variant->file;
  std::error_code ec;
  if (!fs::is_regular_file(result.source, ec)) {
    throw Error("the truth metadata registered in " + collection_file +
                    " does not exist",
                Location(result.source.string()));
  }

  // Outputs: refuse to overwrite the inputs ever, and anything else without
  // --force.
  result.output = options.output.empty()
                      ? collection.root() / DefaultOutputName(options.spec.seed)
                      : options.output;
  const fs::path output_canonical = fs::weakly_canonical(result.output);
  if (output_canonical == fs::weakly_canonical(result.source) ||
      output_canonical == fs::weakly_canonical(collection.collection_path())) {
    throw Error(
        "the output would replace an input of the collection; choose another "
        "-o",
        Location(result.output.string()));
  }
  if (fs::is_directory(result.output, ec)) {
    throw Error("the output is a folder; -o takes a file name",
                Location(result.output.string()));
  }
  RefuseToOverwrite(result.output, options.force, "output metadata");
  if (options.report) {
    fs::path report = options.report_path;
    if (report.empty()) {
      report = result.output;
      report.replace_extension(".report.json");
    }
    if (fs::weakly_canonical(report) == output_canonical) {
      throw Error("the report and the output metadata are the same file",
                  Location(report.string()));
    }
    RefuseToOverwrite(report, options.force, "report");
    result.report = report;
  }
  result.registered_as = RelativeInside(result.output, collection.root());

  const MetadataReader truth(result.source);
  if (truth.header().perturbed) {
    throw Error("the metadata registered as truth is itself perturbed",
                Location(result.source.string(), "/perturbed"));
  }

  // Pass 1: the realized errors' statistics, which the output states in its
  // header.
  ErrorStatistics statistics;
  {
    MetadataPerturber perturber(options.spec, world);
    truth.ForEachFrame([&](const MetadataFrame& frame) {
      statistics.Add(perturber.NextError(frame.index, frame.time));
    });
  }
  result.summary = statistics.ToJson();
  result.frames = statistics.count();

  // Pass 2: the perturbed frames (the same draws again; they depend only on
  // seed, field and frame).
  MetadataHeader out_header;
  out_header.format_version = truth.header().format_version;
  out_header.perturbed = true;
  out_header.noise = NoiseRecord{NoiseModelName(options.spec.model),
                                 options.spec.ParametersJson(world),
                                 options.spec.seed};
  out_header.source = truth_variant->file;
  out_header.frame_count = truth.header().frame_count;
  MetadataWriter writer(
      result.output, out_header, {{"summary", result.summary}});
  {
    const MetadataReader again(result.source,
                               ReaderOptions{false});  // validated in pass 1
    MetadataPerturber perturber(options.spec, world);
    std::unique_ptr<Progress> progress;
    if (options.progress)
      progress = std::make_unique<Progress>("perturb-metadata", result.frames);
    again.ForEachFrame([&](const MetadataFrame& frame) {
      writer.Append(perturber.Perturb(frame));
      if (progress) progress->Add();
    });
  }

  // Pass over collection.json: the header rewritten with the new variant, the
  // frames copied as they are, and the report measured on the way. Both files
  // stay temporary until everything succeeded.
  std::unique_ptr<JsonArrayWriter> registry;
  if (!result.registered_as.empty()) {
    nlohmann::json collection_json;
    StreamJsonArrayMember(
        collection.collection_path(), "frames", &collection_json, nullptr);
    nlohmann::json entry = {{"file", result.registered_as},
                            {"perturbed", true},
                            {"description", options.spec.Describe()}};
    nlohmann::json& variants = collection_json["metadata"];
    bool replaced = false;
    for (nlohmann::json& variant : variants) {
      if (variant.value("file", "") == result.registered_as) {
        variant = entry;
        replaced = true;
      }
    }
    if (!replaced) variants.push_back(entry);
    registry = std::make_unique<JsonArrayWriter>(
        collection.collection_path(), collection_json, "frames");
  }
  std::unique_ptr<ReportWriter> report;
  DisplacementSummary displacement;
  MetadataPerturber report_perturber(options.spec, world);
  if (result.report) {
    report = std::make_unique<ReportWriter>(
        *result.report,
        nlohmann::json{{"format", "lsds-perturb-report"},
                       {"metadata", result.output.filename().string()},
                       {"model", NoiseModelName(options.spec.model)},
                       {"seed", options.spec.seed}});
  }
  if (registry || report) {
    collection.ForEachFrameJson(
        [&](const nlohmann::json& json, const std::string& pointer) {
          if (registry) registry->Append(json);
          if (!report) return;
          const Frame frame = FrameFromJson(json, collection_file, pointer);
          // The measured camera, from the truth as metadata.json states it
          // (TruthMetadata) and the same realized error as the output's frame
          // of that index.
          const MetadataFrame measured =
              report_perturber.Perturb(TruthMetadata(frame, world));
          const FrameDisplacement moved =
              MeasureDisplacement(frame, world, measured);
          displacement.Add(moved);
          report->Append(moved);
        });
  }

  writer.Commit();
  if (report) {
    result.report_summary = displacement.ToJson();
    report->Finish(*result.report_summary);
    report->Commit();
  }
  if (registry) registry->Commit();
  return result;
}

}  // namespace lsds::noise
