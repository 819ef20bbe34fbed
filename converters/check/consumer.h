// The interface of one consumer's checker: its rules (each with the loader
// line it is ported from) and a function that applies them to an export.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "converters/check/finding.h"

namespace lsds::check {

struct CheckOptions {
  // The class names a DOTA consumer is configured with (MMRotate's
  // `classes=`); empty: the 15 classes of DOTA v1.0, MMRotate's default.
  std::vector<std::string> dota_classes;
};

// Collects one consumer's findings into a report; the severity comes from the
// consumer's rule table, so every finding names a documented rule.
class FindingSink {
 public:
  FindingSink(std::string consumer,
              const std::vector<Rule>& rules,
              std::filesystem::path dir,
              ExportReport* report)
      : consumer_(std::move(consumer)), rules_(rules), dir_(std::move(dir)), report_(report) {}

  // `file` is a path under the export folder (written relative to it).
  void Add(const std::string& rule,
           const std::filesystem::path& file,
           int64_t line,
           const std::string& message);
  void CountFile() { ++report_->files; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::string consumer_;
  const std::vector<Rule>& rules_;
  std::filesystem::path dir_;
  ExportReport* report_;
};

using CheckFunction = void (*)(const std::string& format,
                               const std::filesystem::path& dir,
                               const CheckOptions& options,
                               FindingSink* sink);

struct Consumer {
  const char* name;                  // "ultralytics"
  const char* reads;                 // what of the consumer is ported, for help and docs
  std::vector<std::string> formats;  // lsds convert format names it reads
  const std::vector<Rule>& (*rules)();
  CheckFunction check;
};

// One per consumer file.
const std::vector<Rule>& UltralyticsRules();
void CheckUltralytics(const std::string& format,
                      const std::filesystem::path& dir,
                      const CheckOptions& options,
                      FindingSink* sink);
const std::vector<Rule>& MmrotateRules();
void CheckMmrotate(const std::string& format,
                   const std::filesystem::path& dir,
                   const CheckOptions& options,
                   FindingSink* sink);
const std::vector<Rule>& DatumaroRules();
void CheckDatumaro(const std::string& format,
                   const std::filesystem::path& dir,
                   const CheckOptions& options,
                   FindingSink* sink);
const std::vector<Rule>& DotaDevkitRules();
void CheckDotaDevkit(const std::string& format,
                     const std::filesystem::path& dir,
                     const CheckOptions& options,
                     FindingSink* sink);
const std::vector<Rule>& TrackEvalRules();
void CheckTrackEval(const std::string& format,
                    const std::filesystem::path& dir,
                    const CheckOptions& options,
                    FindingSink* sink);
const std::vector<Rule>& PycocotoolsRules();
void CheckPycocotools(const std::string& format,
                      const std::filesystem::path& dir,
                      const CheckOptions& options,
                      FindingSink* sink);

}  // namespace lsds::check
