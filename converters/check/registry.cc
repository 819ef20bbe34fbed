#include "converters/check/registry.h"

#include <algorithm>
#include <system_error>

#include "libs/util/check.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace fs = std::filesystem;

const char* SeverityName(Severity severity) {
  switch (severity) {
    case Severity::kIgnored:
      return "ignored";
    case Severity::kDroppedBox:
      return "dropped-box";
    case Severity::kDroppedImage:
      return "dropped-image";
    case Severity::kRejected:
      return "rejected";
  }
  return "rejected";
}

int64_t ExportReport::Count(Severity severity) const {
  return std::count_if(
      findings.begin(), findings.end(), [&](const Finding& f) { return f.severity == severity; });
}

bool ExportReport::Fails() const {
  return std::any_of(findings.begin(), findings.end(), [](const Finding& f) {
    return f.severity != Severity::kIgnored;
  });
}

void FindingSink::Add(const std::string& rule,
                      const fs::path& file,
                      int64_t line,
                      const std::string& message) {
  const auto it =
      std::find_if(rules_.begin(), rules_.end(), [&](const Rule& r) { return rule == r.id; });
  if (it == rules_.end())
    throw InternalError("check-export: rule '" + rule + "' is not registered");
  std::error_code error;
  const fs::path relative = file.lexically_relative(dir_);
  Finding finding;
  finding.consumer = consumer_;
  finding.rule = rule;
  finding.severity = it->severity;
  finding.file =
      relative.empty() || relative.native().rfind("..", 0) == 0 ? file.string() : relative.string();
  finding.line = line;
  finding.message = message;
  report_->findings.push_back(std::move(finding));
}

const std::vector<Consumer>& Consumers() {
  static const std::vector<Consumer> consumers = {
      {"ultralytics",
       "Ultralytics YOLODataset / verify_image_label",
       {"yolo", "yolo-seg", "yolo-obb"},
       UltralyticsRules,
       CheckUltralytics},
      {"mmrotate", "MMRotate DOTADataset (0.x)", {"dota"}, MmrotateRules, CheckMmrotate},
      {"datumaro", "Datumaro DOTA importer", {"dota"}, DatumaroRules, CheckDatumaro},
      {"dota-devkit", "DOTA devkit parse_dota_poly", {"dota"}, DotaDevkitRules, CheckDotaDevkit},
      {"trackeval",
       "TrackEval MotChallenge2DBox ground truth",
       {"mot"},
       TrackEvalRules,
       CheckTrackEval},
      {"pycocotools",
       "pycocotools COCO index and COCOeval",
       {"coco"},
       PycocotoolsRules,
       CheckPycocotools},
  };
  return consumers;
}

std::vector<std::string> CheckedFormats() {
  std::vector<std::string> formats;
  for (const Consumer& consumer : Consumers()) {
    for (const std::string& format : consumer.formats) {
      if (std::find(formats.begin(), formats.end(), format) == formats.end())
        formats.push_back(format);
    }
  }
  return formats;
}

std::vector<std::string> ConsumerNames(const std::string& format) {
  std::vector<std::string> names;
  for (const Consumer& consumer : Consumers()) {
    if (std::find(consumer.formats.begin(), consumer.formats.end(), format) !=
        consumer.formats.end())
      names.emplace_back(consumer.name);
  }
  return names;
}

ExportReport CheckExport(const std::string& format,
                         const fs::path& dir,
                         const std::string& consumer,
                         const CheckOptions& options) {
  const std::vector<std::string> formats = CheckedFormats();
  if (std::find(formats.begin(), formats.end(), format) == formats.end()) {
    throw Error("unknown format '" + format + "'" + DidYouMean(format, formats) +
                    " (check-export reads " + Join(formats, ", ") + ")",
                Location("FORMAT"));
  }
  const std::vector<std::string> names = ConsumerNames(format);
  if (!consumer.empty() && std::find(names.begin(), names.end(), consumer) == names.end()) {
    std::vector<std::string> all;
    for (const Consumer& c : Consumers()) all.emplace_back(c.name);
    const bool known = std::find(all.begin(), all.end(), consumer) != all.end();
    throw Error((known ? "consumer '" + consumer + "' does not read " + format
                       : "unknown consumer '" + consumer + "'" + DidYouMean(consumer, all)) +
                    "; " + format + " is read by " + Join(names, ", "),
                Location("--consumer"));
  }
  std::error_code error;
  if (!fs::is_directory(dir, error)) throw Error("not a folder", Location(dir.string()));
  fs::directory_iterator probe(dir, error);
  if (error) throw Error("cannot read the folder: " + error.message(), Location(dir.string()));
  ExportReport report;
  report.format = format;
  report.dir = dir.string();
  for (const Consumer& c : Consumers()) {
    if (std::find(names.begin(), names.end(), c.name) == names.end()) continue;
    if (!consumer.empty() && consumer != c.name) continue;
    report.consumers.emplace_back(c.name);
    FindingSink sink(c.name, c.rules(), dir, &report);
    c.check(format, dir, options, &sink);
  }
  return report;
}

}  // namespace lsds::check
