// Report writers: text for people, JSON for machines
// (schemas/validate-report.schema.json), JUnit XML for CI systems (one test
// case per selected check).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "validators/report.h"

namespace lsds::validate {

// Grouped by check, counted, the first `max_shown` findings of each with their
// location, and a one-line verdict against `fail_on`.
std::string ReportToText(const Report& report, Severity fail_on, size_t max_shown = 5);
nlohmann::json ReportToJson(const Report& report, Severity fail_on);
std::string ReportToJUnit(const Report& report, Severity fail_on);
// The JUnit report of a run whose input could not be read (exit 2): one
// failing testcase naming the input and the error, so a CI page shows why.
std::string UnreadableInputToJUnit(const std::string& collection,
                                   const std::string& message,
                                   double seconds);
// One finding and its location as the JSON report writes them (also used by
// the partial reports of `validate --shard`).
nlohmann::json LocationToJson(const Location& location);
nlohmann::json FindingToJson(const Finding& finding);
std::string Verdict(const Report& report, Severity fail_on);

// The report in `format` ("text", "json" or "junit") as `lsds validate` and
// `lsds merge-reports` print it (text shows up to 5 findings per check).
std::string RenderReport(const Report& report, const std::string& format, Severity fail_on);

}  // namespace lsds::validate
