// What `lsds check-export` reports: one finding per image, label line, box or
// frame that a consumer of an export would drop or reject, typed by how much
// that consumer loses (docs/check-export.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lsds::check {

enum class Severity {
  kIgnored = 0,       // skipped as the format intends (MOT zero-marked lines); never a failure
  kDroppedBox = 1,    // one box, line or segment is lost; the rest of the image is kept
  kDroppedImage = 2,  // the whole image, label file or sequence is lost
  kRejected = 3,      // the consumer stops with an error: nothing is loaded
};
const char* SeverityName(Severity severity);  // "ignored", "dropped-box", ...

// One rule of a consumer's loader, ported with the place it comes from.
struct Rule {
  const char* id;      // "ultralytics.coordinate-range"
  Severity severity;   // what breaking it costs
  const char* source;  // "ultralytics/data/utils.py:219 (00bfe34)"
  const char* what;    // one line for the docs and JUnit
};

struct Finding {
  std::string consumer;  // "ultralytics"
  std::string rule;      // a Rule::id of that consumer
  Severity severity = Severity::kRejected;
  std::string file;  // relative to the export folder
  int64_t line = 0;  // 1-based; 0 when the finding is about a whole file
  std::string message;
};

// The outcome of one check-export run.
struct ExportReport {
  std::string format;                  // the lsds convert format name
  std::string dir;                     // the export folder as given
  std::vector<std::string> consumers;  // the consumers applied, registry order
  std::vector<Finding> findings;       // in the order found (per consumer, file order)
  int64_t files = 0;                   // label, annotation and image files read
  int64_t Count(Severity severity) const;
  // True when a finding other than kIgnored exists (exit 1).
  bool Fails() const;
};

}  // namespace lsds::check
