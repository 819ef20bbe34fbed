// The validation summary of the page, from an `lsds validate --format json`
// report (schemas/validate-report.schema.json): verdict, counts, and per check
// the findings kept, each linked to its frame's card when the frame is on the
// contact sheet.
//
// The report is read typed before anything is written: a value of the wrong
// type or out of range is an lsds::Error naming the file and the JSON pointer
// (exit 2), and the section is written from the typed values only.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "report/html_text.h"

namespace lsds::report {

struct ValidationFinding {
  std::string severity;  // "error", "warning" or "info"
  std::string check;
  std::string object;  // may be empty
  std::string message;
  std::string file;  // relative to the collection; may be empty
  std::string json_pointer;
  int64_t line = 0, column = 0;  // 0: none
  std::optional<int64_t> frame;
  std::optional<std::array<int64_t, 2>> pixel;
};

struct ValidationCheck {
  std::string id;
  std::string severity;
  int64_t count = 0;  // every finding; `findings` holds the first ones
  std::vector<ValidationFinding> findings;
};

struct ValidationSummary {
  std::string verdict;  // "pass" or "fail"
  std::string fail_on;
  int64_t frames = 0;
  int64_t errors = 0, warnings = 0, notes = 0;
  std::vector<ValidationCheck> checks;
};

// Reads a parsed report: its format, then its schema, then every value the
// page shows. Throws lsds::Error at `file#pointer`.
ValidationSummary ReadValidationReport(const nlohmann::json& report, const std::string& file);
// The same from the file's text: nesting limit and syntax errors at
// line:column first (libs/util/limits.h, json_errors.h).
ValidationSummary ParseValidationReport(std::string_view text, const std::string& file);

// Frame indices the findings point to (at most `max`), in frame order.
std::set<int64_t> FramesWithFindings(const ValidationSummary& validation, size_t max);

Html ValidationSection(const ValidationSummary& validation,
                       const std::set<int64_t>& frames_on_sheet);

}  // namespace lsds::report
