// `lsds perturb-metadata` as a library call: writes a perturbed copy of a
// collection's truth metadata, registers it as a metadata variant in
// collection.json (header only; frames, layers and the original metadata are
// left as they are) and optionally reports what the noise does to the projected
// targets.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "perturb/noise_spec.h"
#include "perturb/projection_report.h"

namespace lsds::noise {

struct PerturbOptions {
  std::filesystem::path collection;  // the collection folder
  std::filesystem::path output;      // empty: COLLECTION/metadata.perturbed-<seed>.json
  bool force = false;                // overwrite an existing output (and report)
  NoiseSpec spec;
  bool report = false;
  std::filesystem::path report_path;  // empty: the output with ".report.json" for ".json"
  bool progress = true;               // a progress line on a terminal
};

struct PerturbResult {
  std::filesystem::path output;
  std::filesystem::path source;  // the truth metadata that was perturbed
  std::string registered_as;     // the variant's "file" in collection.json; empty
                                 // if not registered
  int64_t frames = 0;
  nlohmann::json summary;  // realized error statistics (also in the output's "summary")
  std::optional<std::filesystem::path> report;
  std::optional<nlohmann::json> report_summary;
};

// Throws lsds::Error (and writes nothing) on bad options, a collection without
// truth metadata or an existing output without `force`. Same options ->
// byte-identical output.
PerturbResult PerturbCollection(const PerturbOptions& options);

// The default output name for a seed: "metadata.perturbed-<seed>.json".
std::string DefaultOutputName(uint64_t seed);

}  // namespace lsds::noise
