// The check-export report as text (one finding a line, `file:line: consumer:
// rule: message`), JSON (schemas/check-export-report.schema.json) and JUnit
// XML (one test case per rule of each consumer applied).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "converters/check/finding.h"

namespace lsds::check {

nlohmann::json ReportToJson(const ExportReport& report);
std::string ReportToText(const ExportReport& report);
std::string ReportToJUnit(const ExportReport& report);
// "FAIL: 3 finding(s) (1 rejected, ...) from ultralytics" or "PASS: ...".
std::string Verdict(const ExportReport& report);
// `format` is "text", "json" or "junit".
std::string RenderReport(const ExportReport& report, const std::string& format);

}  // namespace lsds::check
