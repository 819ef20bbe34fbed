// `lsds validate --shard I/N` and `lsds merge-reports`: a shard's share of a
// validation run, and the join of N shares into the report a single run gives.
//
// Why the join equals the single run: every finding about a frame comes from
// the one shard that owns the frame (index % N == I), the findings about the
// collection as a whole from shard 0, and the checks that need every frame
// (class balance, metadata pose agreement) run once, at the join, on tallies
// summed over the shards (CollectionTallies). Examples are kept per check in
// frame order, so the first `max_examples` of the union are the single run's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/collection/model.h"
#include "libs/collection/requirement_summary.h"
#include "validators/checks.h"
#include "validators/report.h"

namespace lsds::validate {

// What the whole-collection checks (stats.class-unused, stats.class-imbalance,
// cross.metadata-pose) need from every frame.
struct CollectionTallies {
  bool header_read = false;  // the checks below need the class table
  std::vector<ClassInfo> classes;
  bool has_classid_layer = false;
  std::map<uint32_t, int64_t> objects_per_class;
  std::set<uint32_t> pixel_classes;  // class ids seen in classid layers
  struct Metadata {
    std::string file;
    bool perturbed = false;
    Statistic position_error, angle_error;
    int64_t mismatched = 0;
    std::optional<int64_t> first_mismatch;  // the smallest frame index
  };
  std::vector<Metadata> metadata;
  // The LCAP requirements asked (provenance.requirements; null without) and what the frames
  // achieved of them.
  nlohmann::json requirements_asked;
  RequirementSummary requirements;

  // Adds another shard's frame tallies (the header parts must agree).
  void MergeFrom(const CollectionTallies& other);
};

// Runs the whole-collection checks on tallies of every frame.
void FinishCollectionChecks(const CollectionTallies& tallies,
                            const CheckSelection& checks,
                            Report* report);

struct PartialReport {
  int shard_index = 0;
  int shard_count = 1;
  std::string collection;           // as given to the shard's command
  std::string collection_digest;    // of collection.json: the same input
  std::vector<std::string> checks;  // the selected ids, registry order
  Report report{20};
  CollectionTallies tallies;
};

// The partial report file (format "lsds-validate-partial"; documented in
// docs/validate.md). Doubles are written so that they read back exactly.
nlohmann::json PartialReportToJson(const PartialReport& partial);
// Throws lsds::Error naming `file` and the JSON pointer of what is wrong.
PartialReport PartialReportFromJson(const nlohmann::json& json, const std::string& file);

// Reads the partial reports of one run and joins them. Throws lsds::Error
// (exit 2) naming the file when they are not N shards of the same collection,
// checks and options, each exactly once.
Report MergePartialReports(const std::vector<std::filesystem::path>& files);

// A digest of a file's bytes (FNV-1a 64, hex): tells two inputs apart.
std::string FileDigest(const std::filesystem::path& path);

}  // namespace lsds::validate
