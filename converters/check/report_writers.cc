#include "converters/check/report_writers.h"

#include <algorithm>
#include <sstream>

#include "converters/check/registry.h"
#include "libs/util/junit.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace {

std::string Place(const Finding& f) {
  return f.line > 0 ? f.file + ":" + std::to_string(f.line) : f.file;
}

std::string Line(const Finding& f) {
  return Place(f) + ": " + f.consumer + ": " + f.rule + ": " + f.message;
}

const Severity kSeverities[] = {
    Severity::kRejected, Severity::kDroppedImage, Severity::kDroppedBox, Severity::kIgnored};

}  // namespace

std::string Verdict(const ExportReport& report) {
  std::vector<std::string> counts;
  for (Severity s : kSeverities)
    counts.push_back(std::to_string(report.Count(s)) + " " + SeverityName(s));
  return std::string(report.Fails() ? "FAIL" : "PASS") + ": " +
         std::to_string(report.findings.size()) + " finding(s) (" + Join(counts, ", ") + ") in " +
         std::to_string(report.files) + " file(s) of " + report.format + " read as " +
         Join(report.consumers, ", ") + " read them";
}

std::string ReportToText(const ExportReport& report) {
  std::ostringstream out;
  for (const Finding& f : report.findings) out << Line(f) << "\n";
  out << Verdict(report) << "\n";
  return out.str();
}

nlohmann::json ReportToJson(const ExportReport& report) {
  nlohmann::json j;
  j["format"] = "lsds-check-export-report";
  j["format_version"] = "1.0";
  j["export_format"] = report.format;
  j["dir"] = report.dir;
  j["verdict"] = report.Fails() ? "fail" : "pass";
  j["files"] = report.files;
  nlohmann::json counts = nlohmann::json::object();
  for (Severity s : kSeverities) counts[SeverityName(s)] = report.Count(s);
  j["counts"] = counts;
  j["consumers"] = report.consumers;
  nlohmann::json findings = nlohmann::json::array();
  for (const Finding& f : report.findings) {
    nlohmann::json item = {{"consumer", f.consumer},
                           {"rule", f.rule},
                           {"severity", SeverityName(f.severity)},
                           {"file", f.file},
                           {"message", f.message}};
    if (f.line > 0) item["line"] = f.line;
    findings.push_back(item);
  }
  j["findings"] = findings;
  return j;
}

std::string ReportToJUnit(const ExportReport& report) {
  JUnitSuite suite;
  suite.suites_name = "lsds check-export";
  suite.name = report.format + " " + report.dir;
  suite.time = "0";
  for (const Consumer& consumer : Consumers()) {
    if (std::find(report.consumers.begin(), report.consumers.end(), consumer.name) ==
        report.consumers.end())
      continue;
    for (const Rule& rule : consumer.rules()) {
      JUnitCase c;
      c.classname = std::string("lsds.check-export.") + consumer.name;
      c.name = rule.id;
      c.time = "0";
      std::ostringstream body;
      int64_t failing = 0, total = 0;
      const Finding* first = nullptr;
      for (const Finding& f : report.findings) {
        if (f.consumer != consumer.name || f.rule != rule.id) continue;
        ++total;
        if (f.severity != Severity::kIgnored) ++failing;
        if (first == nullptr) first = &f;
        body << Line(f) << "\n";
      }
      c.body = body.str();
      if (failing > 0) {
        c.outcome = JUnitCase::Outcome::kFailure;
        c.failure_message =
            std::to_string(total) + " finding(s): " + Place(*first) + ": " + first->message;
        c.failure_type = SeverityName(rule.severity);
      } else if (total > 0) {
        c.outcome = JUnitCase::Outcome::kOutput;
      }
      suite.cases.push_back(c);
    }
  }
  return JUnitXml(suite);
}

std::string RenderReport(const ExportReport& report, const std::string& format) {
  if (format == "json")
    return ReportToJson(report).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
           "\n";
  if (format == "junit") return ReportToJUnit(report);
  return ReportToText(report);
}

}  // namespace lsds::check
