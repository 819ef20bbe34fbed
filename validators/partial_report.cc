#include "validators/partial_report.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <fstream>

#include "libs/collection/json_stream.h"
#include "libs/collection/schema.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "validators/report_writers.h"

namespace lsds::validate {

namespace fs = std::filesystem;

void CollectionTallies::MergeFrom(const CollectionTallies& other) {
  MergeRequirementSummary(other.requirements, &requirements);
  for (const auto& [id, n] : other.objects_per_class) objects_per_class[id] += n;
  pixel_classes.insert(other.pixel_classes.begin(), other.pixel_classes.end());
  for (size_t k = 0; k < metadata.size() && k < other.metadata.size(); ++k) {
    Metadata& mine = metadata[k];
    const Metadata& theirs = other.metadata[k];
    for (auto [a, b] : {std::pair{&mine.position_error, &theirs.position_error},
                        {&mine.angle_error, &theirs.angle_error}}) {
      a->max = std::max(a->max, b->max);
      a->sum_squares += b->sum_squares;
      a->count += b->count;
    }
    mine.mismatched += theirs.mismatched;
    if (theirs.first_mismatch &&
        (!mine.first_mismatch || *theirs.first_mismatch < *mine.first_mismatch))
      mine.first_mismatch = theirs.first_mismatch;
  }
}

namespace {

std::string CountList(const std::vector<int64_t>& counts) {
  std::string s = "[";
  for (size_t i = 0; i < counts.size(); ++i) s += (i ? "," : "") + std::to_string(counts[i]);
  return s + "]";
}

// requirements.met and requirements.quota (docs/validate.md): the demands the rendered truth
// missed, and each quota's achieved counts against its planned ones. A collection that holds part
// of a run (other frames than the quota's planned counts add up to) is not judged by its quotas.
template <typename Emit>
void CheckRequirements(const CollectionTallies& tallies, const Emit& emit) {
  const nlohmann::json& asked = tallies.requirements_asked;
  if (asked.is_null()) return;
  const RequirementSummary summary = FoldSteps(asked, tallies.requirements);
  const std::string unit = asked.value("unit", "frame") == "step" ? "step" : "frame";
  if (!summary.missed.empty()) {
    std::string list;
    for (size_t i = 0; i < summary.missed.size() && i < 10; ++i)
      list += (i ? ", " : "") + std::to_string(summary.missed[i]);
    if (summary.missed.size() > 10) list += ", ...";
    Location where(kCollectionFile, "/frames");
    if (unit == "frame") where.frame = summary.missed.front();
    emit("requirements.met",
         where,
         std::to_string(summary.missed.size()) + " of " + std::to_string(summary.frames) + " " +
             unit + "s missed their requirements in the rendered truth (" + unit + "s " + list +
             ")");
  }
  const nlohmann::json& quotas = asked.at("quotas");
  for (size_t q = 0; q < quotas.size() && q < summary.achieved.size(); ++q) {
    const std::vector<int64_t> planned = quotas[q].at("planned").get<std::vector<int64_t>>();
    int64_t total = 0;
    for (const int64_t n : planned) total += n;
    if (total != summary.frames) continue;
    std::vector<int64_t> achieved = summary.achieved[q].second;
    const int64_t outside = achieved.back();
    achieved.pop_back();
    const double tolerance = quotas[q].value("tolerance", 0.05);
    int64_t worst = 0;
    for (size_t b = 0; b < planned.size() && b < achieved.size(); ++b)
      worst = std::max(worst, std::abs(achieved[b] - planned[b]));
    if (static_cast<double>(worst) <= tolerance * static_cast<double>(total)) continue;
    emit("requirements.quota",
         Location(kCollectionFile, "/provenance/requirements/quotas/" + std::to_string(q)),
         "quota " + quotas[q].at("name").get<std::string>() + " (" +
             quotas[q].at("quantity").get<std::string>() + ", " + QuotaBinsText(quotas[q]) +
             "): planned " + CountList(planned) + " " + unit + "s, achieved " +
             CountList(achieved) +
             (outside ? " (" + std::to_string(outside) + " outside every bin)" : "") +
             "; a bin is off by " + std::to_string(worst) + ", over the tolerance " +
             FormatNumber(tolerance) + " x " + std::to_string(total));
  }
}

}  // namespace

void FinishCollectionChecks(const CollectionTallies& tallies,
                            const CheckSelection& checks,
                            Report* report) {
  if (!tallies.header_read) return;
  auto emit = [&](const std::string& id, Location where, const std::string& message) {
    if (!checks.Has(id)) return;
    report->Add({GetCheck(id).severity, id, std::move(where), "", message});
  };
  for (const CollectionTallies::Metadata& file : tallies.metadata) {
    report->MergeStatistic("cross.metadata-pose." + file.file + ".position_error",
                           file.position_error);
    report->MergeStatistic("cross.metadata-pose." + file.file + ".angle_error_deg",
                           file.angle_error);
    if (file.mismatched > 0 && !file.perturbed) {
      Location where(file.file, "/frames");
      where.frame = file.first_mismatch;
      emit("cross.metadata-pose",
           where,
           std::to_string(file.mismatched) + " frame(s) differ from truth (max position error " +
               std::to_string(file.position_error.max) + " world units, max attitude error " +
               std::to_string(file.angle_error.max) +
               " deg) but the file is not declared perturbed");
    }
  }
  CheckRequirements(tallies, emit);
  int64_t most = 0, least = -1;
  std::string most_name, least_name;
  for (size_t k = 0; k < tallies.classes.size(); ++k) {
    const ClassInfo& c = tallies.classes[k];
    const auto it = tallies.objects_per_class.find(c.id);
    const int64_t n = it == tallies.objects_per_class.end() ? 0 : it->second;
    // Without a classid layer, pixels cannot tell whether a class without
    // objects (the terrain) is drawn: only what is declared is checked.
    if (n == 0 && tallies.pixel_classes.count(c.id) == 0 && tallies.has_classid_layer) {
      emit("stats.class-unused",
           Location(kCollectionFile, "/classes/" + std::to_string(k)),
           "class " + std::to_string(c.id) + " '" + c.name + "' has no object and no pixel");
    }
    if (n > most) most = n, most_name = c.name;
    if (n > 0 && (least < 0 || n < least)) least = n, least_name = c.name;
  }
  if (least > 0 && most >= 100 * least) {
    emit("stats.class-imbalance",
         Location(kCollectionFile, "/classes"),
         "class '" + most_name + "' has " + std::to_string(most) + " objects, class '" +
             least_name + "' only " + std::to_string(least));
  }
}

namespace {

constexpr const char* kPartialFormat = "lsds-validate-partial";

nlohmann::json SumToJson(const Statistic& s) {
  return {{"max", s.max}, {"sum_squares", s.sum_squares}, {"count", s.count}};
}

Statistic SumFromJson(const nlohmann::json& j) {
  Statistic s;
  s.max = j.at("max").get<double>();
  s.sum_squares = j.at("sum_squares").get<double>();
  s.count = j.at("count").get<int64_t>();
  return s;
}

Location LocationFromJson(const nlohmann::json& j) {
  Location where;
  if (j.contains("file")) where.file = j["file"].get<std::string>();
  if (j.contains("line")) where.line = j["line"].get<int>();
  if (j.contains("column")) where.column = j["column"].get<int>();
  if (j.contains("json_pointer")) where.json_pointer = j["json_pointer"].get<std::string>();
  if (j.contains("frame")) where.frame = j["frame"].get<int64_t>();
  if (j.contains("pixel")) {
    where.pixel_x = j["pixel"][0].get<int>();
    where.pixel_y = j["pixel"][1].get<int>();
  }
  return where;
}

}  // namespace

std::string FileDigest(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(path.string()));
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a 64
  char buffer[1 << 16];
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) {
    for (std::streamsize k = 0; k < in.gcount(); ++k) {
      hash ^= static_cast<unsigned char>(buffer[k]);
      hash *= 0x100000001b3ULL;
    }
  }
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016" PRIx64, hash);
  return hex;
}

nlohmann::json PartialReportToJson(const PartialReport& partial) {
  const Report& report = partial.report;
  nlohmann::json j;
  j["format"] = kPartialFormat;
  j["format_version"] = "1.0";
  j["shard"] = {{"index", partial.shard_index}, {"count", partial.shard_count}};
  j["collection"] = partial.collection;
  j["collection_digest"] = partial.collection_digest;
  j["checks"] = partial.checks;
  j["max_examples"] = report.max_examples();
  j["frames"] = report.frames;
  j["files_decoded"] = report.files_decoded;
  j["bytes_decoded"] = report.bytes_decoded;
  j["seconds"] = report.seconds;
  nlohmann::json results = nlohmann::json::object();
  for (const auto& [id, result] : report.results()) {
    nlohmann::json findings = nlohmann::json::array();
    for (const Finding& f : result.examples) findings.push_back(FindingToJson(f));
    results[id] = {{"counts", result.counts}, {"findings", findings}};
  }
  j["results"] = results;
  nlohmann::json statistics = nlohmann::json::object();
  for (const auto& [name, s] : report.statistics()) statistics[name] = SumToJson(s);
  j["statistics"] = statistics;
  j["check_seconds"] = report.check_seconds();
  const CollectionTallies& t = partial.tallies;
  nlohmann::json classes = nlohmann::json::array();
  for (const ClassInfo& c : t.classes) classes.push_back({{"id", c.id}, {"name", c.name}});
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& [id, n] : t.objects_per_class) objects.push_back({id, n});
  nlohmann::json metadata = nlohmann::json::array();
  for (const CollectionTallies::Metadata& m : t.metadata) {
    nlohmann::json mj = {{"file", m.file},
                         {"perturbed", m.perturbed},
                         {"position_error", SumToJson(m.position_error)},
                         {"angle_error", SumToJson(m.angle_error)},
                         {"mismatched", m.mismatched}};
    if (m.first_mismatch) mj["first_mismatch"] = *m.first_mismatch;
    metadata.push_back(mj);
  }
  j["tallies"] = {{"header_read", t.header_read},
                  {"classes", classes},
                  {"has_classid_layer", t.has_classid_layer},
                  {"objects_per_class", objects},
                  {"pixel_classes", t.pixel_classes},
                  {"metadata", metadata}};
  if (!t.requirements_asked.is_null()) {
    j["tallies"]["requirements_asked"] = t.requirements_asked;
    j["tallies"]["requirements"] = RequirementSummaryToJson(t.requirements);
  }
  return j;
}

PartialReport PartialReportFromJson(const nlohmann::json& json, const std::string& file) {
  if (!json.is_object() || json.value("format", "") != kPartialFormat) {
    throw Error("not a partial validation report (format is not '" + std::string(kPartialFormat) +
                    "'; write one with lsds validate --shard I/N -o FILE)",
                Location(file, "/format"));
  }
  const std::vector<SchemaIssue> issues =
      JsonSchema::Get("validate-partial.schema.json").Validate(json);
  if (!issues.empty()) throw Error(issues.front().message, Location(file, issues.front().pointer));
  PartialReport partial;
  partial.shard_index = json["shard"]["index"].get<int>();
  partial.shard_count = json["shard"]["count"].get<int>();
  if (partial.shard_index >= partial.shard_count) {
    throw Error("shard index " + std::to_string(partial.shard_index) +
                    " is not below the shard count " + std::to_string(partial.shard_count),
                Location(file, "/shard"));
  }
  partial.collection = json["collection"].get<std::string>();
  partial.collection_digest = json["collection_digest"].get<std::string>();
  partial.checks = json["checks"].get<std::vector<std::string>>();
  for (size_t k = 0; k < partial.checks.size(); ++k) {
    try {
      GetCheck(partial.checks[k]);
    } catch (const Error& e) {
      throw Error(e.message(), Location(file, "/checks/" + std::to_string(k)));
    }
  }
  Report report(json["max_examples"].get<size_t>());
  report.collection = partial.collection;
  report.checks = partial.checks;
  report.frames = json["frames"].get<int64_t>();
  report.files_decoded = json["files_decoded"].get<int64_t>();
  report.bytes_decoded = json["bytes_decoded"].get<int64_t>();
  report.seconds = json["seconds"].get<double>();
  for (const auto& [id, result] : json["results"].items()) {
    std::vector<Finding> examples;
    for (const nlohmann::json& f : result["findings"]) {
      Severity severity = Severity::kError;
      ParseSeverity(f["severity"].get<std::string>(), &severity);
      examples.push_back({severity,
                          f["check"].get<std::string>(),
                          LocationFromJson(f["location"]),
                          f.value("object", ""),
                          f["message"].get<std::string>()});
    }
    report.Restore(id, result["counts"].get<std::array<int64_t, 3>>(), std::move(examples));
  }
  for (const auto& [name, s] : json["statistics"].items())
    report.MergeStatistic(name, SumFromJson(s));
  for (const auto& [id, seconds] : json["check_seconds"].items())
    report.AddCheckSeconds(id, seconds.get<double>());
  partial.report = std::move(report);

  const nlohmann::json& t = json["tallies"];
  CollectionTallies& tallies = partial.tallies;
  tallies.header_read = t["header_read"].get<bool>();
  for (const nlohmann::json& c : t["classes"])
    tallies.classes.push_back({c["id"].get<uint32_t>(), c["name"].get<std::string>()});
  tallies.has_classid_layer = t["has_classid_layer"].get<bool>();
  for (const nlohmann::json& pair : t["objects_per_class"])
    tallies.objects_per_class[pair[0].get<uint32_t>()] = pair[1].get<int64_t>();
  for (const nlohmann::json& id : t["pixel_classes"])
    tallies.pixel_classes.insert(id.get<uint32_t>());
  if (t.contains("requirements_asked")) {
    tallies.requirements_asked = t["requirements_asked"];
    tallies.requirements = RequirementSummaryFromJson(t.at("requirements"));
  }
  for (const nlohmann::json& m : t["metadata"]) {
    CollectionTallies::Metadata metadata;
    metadata.file = m["file"].get<std::string>();
    metadata.perturbed = m["perturbed"].get<bool>();
    metadata.position_error = SumFromJson(m["position_error"]);
    metadata.angle_error = SumFromJson(m["angle_error"]);
    metadata.mismatched = m["mismatched"].get<int64_t>();
    if (m.contains("first_mismatch")) metadata.first_mismatch = m["first_mismatch"].get<int64_t>();
    tallies.metadata.push_back(std::move(metadata));
  }
  return partial;
}

Report MergePartialReports(const std::vector<fs::path>& files) {
  if (files.empty()) throw Error("no partial reports given");
  std::vector<PartialReport> partials;
  std::vector<std::string> names;
  for (const fs::path& path : files) {
    nlohmann::json json;
    StreamJsonArrayMember(path, "", &json, nullptr);  // located syntax errors
    partials.push_back(PartialReportFromJson(json, path.string()));
    names.push_back(path.string());
  }
  const PartialReport& first = partials.front();
  const int count = first.shard_count;
  std::vector<int> owner(static_cast<size_t>(count), -1);
  for (size_t k = 0; k < partials.size(); ++k) {
    const PartialReport& p = partials[k];
    auto differ = [&](const std::string& what, const std::string& pointer) {
      throw Error(
          what + " differs from " + names.front() + "'s: the reports are not shards of one run",
          Location(names[k], pointer));
    };
    if (p.shard_count != count) differ("the shard count", "/shard/count");
    if (p.collection_digest != first.collection_digest)
      differ("collection.json (its digest)", "/collection_digest");
    if (p.checks != first.checks) differ("the selected checks", "/checks");
    if (p.report.max_examples() != first.report.max_examples())
      differ("--max-examples", "/max_examples");
    int& slot = owner[static_cast<size_t>(p.shard_index)];
    if (slot >= 0) {
      throw Error("shard " + std::to_string(p.shard_index) + "/" + std::to_string(count) +
                      " is given twice (also " + names[static_cast<size_t>(slot)] + ")",
                  Location(names[k], "/shard/index"));
    }
    slot = static_cast<int>(k);
  }
  std::vector<std::string> missing;
  for (int i = 0; i < count; ++i) {
    if (owner[static_cast<size_t>(i)] < 0)
      missing.push_back(std::to_string(i) + "/" + std::to_string(count));
  }
  if (!missing.empty()) {
    std::string list;
    for (const std::string& m : missing) list += (list.empty() ? "" : ", ") + m;
    throw Error("shard(s) " + list + " missing: every shard of the run is needed",
                Location(names.front(), "/shard"));
  }
  // Shard 0 first: its collection-wide findings come first, as in a single run.
  const PartialReport& zero = partials[static_cast<size_t>(owner[0])];
  Report merged(zero.report.max_examples());
  merged.collection = zero.collection;
  merged.checks = zero.checks;
  CollectionTallies tallies = zero.tallies;
  merged.MergeFrom(zero.report);
  for (int i = 1; i < count; ++i) {
    const PartialReport& p = partials[static_cast<size_t>(owner[static_cast<size_t>(i)])];
    merged.MergeFrom(p.report);
    tallies.MergeFrom(p.tallies);
  }
  FinishCollectionChecks(tallies, CheckSelection::Of(merged.checks), &merged);
  return merged;
}

}  // namespace lsds::validate
