#include "report/validation_section.h"

#include <utility>

#include "libs/collection/schema.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"

namespace lsds::report {

namespace {

using nlohmann::json;

// Typed members, each at its JSON pointer when it has the wrong type or range.
// The schema check comes first; these keep the page writer from ever seeing an
// unchecked value, whatever the schema allows.
class Reader {
 public:
  explicit Reader(const std::string& file) : file_(file) {}

  std::string String(const json& object, const std::string& pointer, const char* key) const {
    return AtPointer(file_, pointer + "/" + key, [&] { return object.at(key).get<std::string>(); });
  }
  std::string OptionalString(const json& object,
                             const std::string& pointer,
                             const char* key) const {
    return object.contains(key) ? String(object, pointer, key) : std::string();
  }
  int64_t Integer(const json& object, const std::string& pointer, const char* key) const {
    return AtPointer(
        file_, pointer + "/" + key, [&] { return JsonInteger<int64_t>(object.at(key), key); });
  }
  const json& Member(const json& object, const std::string& pointer, const char* key) const {
    return AtPointer(file_, pointer + "/" + key, [&]() -> const json& { return object.at(key); });
  }
  const json& Array(const json& object, const std::string& pointer, const char* key) const {
    const json& value = Member(object, pointer, key);
    if (!value.is_array()) {
      throw Error(std::string("not an array but ") + value.type_name(),
                  Location(file_, pointer + "/" + key));
    }
    return value;
  }

  ValidationFinding Finding(const json& f, const std::string& at) const {
    ValidationFinding finding;
    finding.severity = String(f, at, "severity");
    finding.check = String(f, at, "check");
    finding.object = OptionalString(f, at, "object");
    finding.message = String(f, at, "message");
    const json& location = Member(f, at, "location");
    const std::string where = at + "/location";
    finding.file = OptionalString(location, where, "file");
    finding.json_pointer = OptionalString(location, where, "json_pointer");
    if (location.contains("line")) finding.line = Integer(location, where, "line");
    if (location.contains("column")) finding.column = Integer(location, where, "column");
    if (location.contains("frame")) finding.frame = Integer(location, where, "frame");
    if (location.contains("pixel")) {
      const json& pixel = Array(location, where, "pixel");
      if (pixel.size() != 2) {
        throw Error("not [x, y]", Location(file_, where + "/pixel"));
      }
      std::array<int64_t, 2> xy{};
      for (size_t i = 0; i < 2; ++i) {
        const std::string name = "pixel/" + std::to_string(i);
        xy[i] = AtPointer(
            file_, where + "/" + name, [&] { return JsonInteger<int64_t>(pixel[i], name); });
      }
      finding.pixel = xy;
    }
    return finding;
  }

 private:
  const std::string& file_;
};

}  // namespace

ValidationSummary ReadValidationReport(const nlohmann::json& report, const std::string& file) {
  if (!report.is_object() || !report.contains("format") ||
      report["format"] != "lsds-validate-report") {
    throw Error(
        "not an lsds validate JSON report (format lsds-validate-report; write one with "
        "lsds validate --format json -o FILE)",
        Location(file, "/format"));
  }
  JsonSchema::Get("validate-report.schema.json").ValidateOrThrow(report, file);
  const Reader read(file);
  ValidationSummary v;
  v.verdict = read.String(report, "", "verdict");
  v.fail_on = read.String(report, "", "fail_on");
  v.frames = read.Integer(report, "", "frames");
  const json& counts = read.Member(report, "", "counts");
  v.errors = read.Integer(counts, "/counts", "error");
  v.warnings = read.Integer(counts, "/counts", "warning");
  v.notes = read.Integer(counts, "/counts", "info");
  const json& checks = read.Array(report, "", "checks");
  for (size_t i = 0; i < checks.size(); ++i) {
    const std::string at = "/checks/" + std::to_string(i);
    ValidationCheck check;
    check.id = read.String(checks[i], at, "id");
    check.severity = read.String(checks[i], at, "severity");
    check.count = read.Integer(checks[i], at, "count");
    const json& findings = read.Array(checks[i], at, "findings");
    for (size_t k = 0; k < findings.size(); ++k) {
      check.findings.push_back(read.Finding(findings[k], at + "/findings/" + std::to_string(k)));
    }
    v.checks.push_back(std::move(check));
  }
  return v;
}

ValidationSummary ParseValidationReport(std::string_view text, const std::string& file) {
  // Before the parse: the schema check recurses.
  CheckJsonNesting(std::string(text), file);
  return ReadValidationReport(ParseJsonText(text, file), file);
}

std::set<int64_t> FramesWithFindings(const ValidationSummary& validation, size_t max) {
  std::set<int64_t> frames;
  for (const ValidationCheck& check : validation.checks) {
    for (const ValidationFinding& f : check.findings) {
      if (frames.size() >= max) return frames;
      if (f.frame) frames.insert(*f.frame);
    }
  }
  return frames;
}

Html ValidationSection(const ValidationSummary& v, const std::set<int64_t>& on_sheet) {
  Html s;
  s << "<section id=\"validation\"><h2>Validation</h2><p class=\"verdict " << v.verdict << "\">"
    << v.verdict << " (fail on " << v.fail_on << "): " << v.errors << " errors, " << v.warnings
    << " warnings, " << v.notes << " notes over " << v.frames << " frames</p>"
    << "<table class=\"findings\"><tr><th>check</th><th>severity</th>"
       "<th>count</th><th>where</th><th>what</th></tr>";
  bool any = false;
  for (const ValidationCheck& check : v.checks) {
    if (check.count == 0) continue;
    any = true;
    s << "<tr class=\"" << check.severity << "\"><td>" << check.id << "</td><td>" << check.severity
      << "</td><td>" << check.count << "</td><td colspan=\"2\">";
    if (check.findings.size() < static_cast<uint64_t>(check.count)) {
      s << "the first " << check.findings.size() << " listed";
    }
    s << "</td></tr>";
    for (const ValidationFinding& f : check.findings) {
      Html where;
      where << f.file;
      if (f.line > 0) where << ":" << f.line << ":" << f.column;
      if (!f.json_pointer.empty()) where << "#" << f.json_pointer;
      if (f.frame) {
        const int64_t frame = *f.frame;
        if (on_sheet.count(frame) > 0) {
          where << " <a href=\"#frame-" << frame << "\" data-goto=\"" << frame << "\">frame "
                << frame << "</a>";
        } else {
          where << " frame " << frame;
        }
      }
      if (f.pixel) where << " pixel (" << (*f.pixel)[0] << ", " << (*f.pixel)[1] << ")";
      s << "<tr class=\"finding\"><td></td><td>" << f.severity << "</td><td></td><td>" << where
        << "</td><td>";
      if (!f.object.empty()) s << f.object << ": ";
      s << f.message << "</td></tr>";
    }
  }
  if (!any) s << "<tr><td colspan=\"5\">no findings</td></tr>";
  s << "</table></section>";
  return s;
}

}  // namespace lsds::report
