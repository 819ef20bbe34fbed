#include "validators/report_writers.h"

#include "libs/util/junit.h"
#include "libs/util/strings.h"
#include "libs/util/text_check.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace lsds::validate {

namespace {

double SecondsOf(const Report& report, const std::string& id) {
  const auto it = report.check_seconds().find(id);
  return it == report.check_seconds().end() ? 0.0 : it->second;
}

// A number as an ostream writes it by default (the JUnit times of earlier
// reports).
std::string DefaultFormat(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string FindingLine(const Finding& f) {
  std::string line = f.location.ToString();
  if (!f.object.empty()) line += " [" + f.object + "]";
  return line + ": " + f.message;
}

}  // namespace

nlohmann::json LocationToJson(const Location& location) {
  nlohmann::json j = nlohmann::json::object();
  if (!location.file.empty()) j["file"] = Utf8Escaped(location.file);
  if (location.line > 0) j["line"] = location.line;
  if (location.column > 0) j["column"] = location.column;
  if (!location.json_pointer.empty()) j["json_pointer"] = location.json_pointer;
  if (location.frame) j["frame"] = *location.frame;
  if (location.pixel_x && location.pixel_y) j["pixel"] = {*location.pixel_x, *location.pixel_y};
  return j;
}

nlohmann::json FindingToJson(const Finding& f) {
  nlohmann::json j = {{"severity", SeverityName(f.severity)},
                      {"check", f.check_id},
                      {"location", LocationToJson(f.location)},
                      {"message", f.message}};
  if (!f.object.empty()) j["object"] = f.object;
  return j;
}

std::string Verdict(const Report& report, Severity fail_on) {
  const int64_t errors = report.Count(Severity::kError),
                warnings = report.Count(Severity::kWarning);
  std::ostringstream out;
  out << (report.Fails(fail_on) ? "FAIL" : "PASS") << ": " << errors << " error(s), " << warnings
      << " warning(s) in " << report.frames << " frame(s), " << report.checks.size()
      << " check(s) (failing on " << SeverityName(fail_on) << ")";
  return out.str();
}

std::string ReportToText(const Report& report, Severity fail_on, size_t max_shown) {
  std::ostringstream out;
  out << "lsds validate " << report.collection << "\n";
  for (const CheckInfo& info : AllChecks()) {  // registry order: schema, structure, layer, ...
    const auto found = report.results().find(info.id);
    if (found == report.results().end()) continue;
    const std::string& id = info.id;
    const CheckResult& result = found->second;
    out << "\n"
        << SeverityName(info.severity) << " " << id << ": " << result.total() << " finding(s) - "
        << info.what << "\n";
    size_t shown = 0;
    for (const Finding& f : result.examples) {
      if (shown++ == max_shown) break;
      out << "  " << FindingLine(f) << "\n";
    }
    if (result.total() > static_cast<int64_t>(std::min(max_shown, result.examples.size()))) {
      out << "  ... and "
          << result.total() - static_cast<int64_t>(std::min(max_shown, result.examples.size()))
          << " more\n";
    }
  }
  if (!report.statistics().empty()) {
    out << "\nstatistics:\n";
    for (const auto& [name, s] : report.statistics()) {
      out << "  " << name << ": max " << s.max << ", rms " << s.rms() << " over " << s.count
          << "\n";
    }
  }
  out << "\n" << Verdict(report, fail_on) << "\n";
  return out.str();
}

nlohmann::json ReportToJson(const Report& report, Severity fail_on) {
  nlohmann::json j;
  j["format"] = "lsds-validate-report";
  j["format_version"] = "1.0";
  j["collection"] = report.collection;
  j["verdict"] = report.Fails(fail_on) ? "fail" : "pass";
  j["fail_on"] = SeverityName(fail_on);
  j["frames"] = report.frames;
  j["files_decoded"] = report.files_decoded;
  j["bytes_decoded"] = report.bytes_decoded;
  j["seconds"] = report.seconds;
  j["counts"] = {{"error", report.Count(Severity::kError)},
                 {"warning", report.Count(Severity::kWarning)},
                 {"info", report.Count(Severity::kInfo)}};
  nlohmann::json checks = nlohmann::json::array();
  for (const std::string& id : report.checks) {
    const CheckInfo& info = GetCheck(id);
    const auto it = report.results().find(id);
    nlohmann::json c = {{"id", id},
                        {"severity", SeverityName(info.severity)},
                        {"tolerance", info.tolerance},
                        {"count", it == report.results().end() ? 0 : it->second.total()},
                        {"seconds", SecondsOf(report, id)}};
    nlohmann::json findings = nlohmann::json::array();
    if (it != report.results().end()) {
      for (const Finding& f : it->second.examples) findings.push_back(FindingToJson(f));
    }
    c["findings"] = findings;
    checks.push_back(c);
  }
  j["checks"] = checks;
  nlohmann::json statistics = nlohmann::json::object();
  for (const auto& [name, s] : report.statistics()) {
    // rms to 9 significant digits: its last bits depend on the order in which
    // threads (and shards) added their sums, its first nine do not.
    statistics[name] = {
        {"max", s.max}, {"rms", std::stod(FormatNumber(s.rms(), 9))}, {"count", s.count}};
  }
  j["statistics"] = statistics;
  return j;
}

std::string ReportToJUnit(const Report& report, Severity fail_on) {
  JUnitSuite suite;
  suite.suites_name = "lsds validate";
  suite.name = report.collection;
  suite.time = DefaultFormat(report.seconds);
  for (const std::string& id : report.checks) {
    JUnitCase c;
    c.classname = "lsds.validate." + id.substr(0, id.find('.'));
    c.name = id;
    char time[32];
    std::snprintf(time, sizeof(time), "%.3f", SecondsOf(report, id));
    c.time = time;
    const auto it = report.results().find(id);
    if (it != report.results().end()) {
      const CheckResult& r = it->second;
      bool failing = false;
      for (int s = static_cast<int>(fail_on); s <= 2; ++s) failing |= r.counts[s] > 0;
      std::ostringstream body;
      for (const Finding& f : r.examples)
        body << SeverityName(f.severity) << " " << FindingLine(f) << "\n";
      if (r.total() > static_cast<int64_t>(r.examples.size())) {
        body << "... and " << r.total() - static_cast<int64_t>(r.examples.size()) << " more\n";
      }
      c.body = body.str();
      if (failing) {
        const std::string summary = std::to_string(r.total()) + " finding(s)";
        c.outcome = JUnitCase::Outcome::kFailure;
        c.failure_message = summary + ": " + (r.examples.empty() ? "" : r.examples.front().message);
        c.failure_type = SeverityName(GetCheck(id).severity);
      } else {
        c.outcome = JUnitCase::Outcome::kOutput;
      }
    }
    suite.cases.push_back(c);
  }
  return JUnitXml(suite);
}

std::string RenderReport(const Report& report, const std::string& format, Severity fail_on) {
  // Messages may quote paths that are not UTF-8: never a type_error 316.
  if (format == "json")
    return ReportToJson(report, fail_on)
               .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
           "\n";
  if (format == "junit") return ReportToJUnit(report, fail_on);
  return ReportToText(report, fail_on, std::min<size_t>(report.max_examples(), 5));
}

std::string UnreadableInputToJUnit(const std::string& collection,
                                   const std::string& message,
                                   double seconds) {
  JUnitSuite suite;
  suite.suites_name = "lsds validate";
  suite.name = collection;
  suite.time = DefaultFormat(seconds);
  JUnitCase c;
  c.classname = "lsds.validate.input";
  c.name = "collection readable";
  c.time = suite.time;
  c.outcome = JUnitCase::Outcome::kFailure;
  c.failure_message = message;
  c.failure_type = "error";
  c.body = collection + ": " + message;
  suite.cases.push_back(c);
  return JUnitXml(suite);
}

}  // namespace lsds::validate
