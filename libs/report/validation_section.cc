#include "libs/report/validation_section.h"

#include <sstream>

#include "libs/report/html.h"

namespace lsds::report {

std::string ValidationSection(const nlohmann::json& v, const std::set<int64_t>& on_sheet) {
  std::ostringstream s;
  const std::string verdict = v.value("verdict", "");
  s << "<section id=\"validation\"><h2>Validation</h2><p class=\"verdict " << HtmlEscape(verdict)
    << "\">" << HtmlEscape(verdict) << " (fail on " << HtmlEscape(v.value("fail_on", "")) << "): ";
  if (v.contains("counts") && v["counts"].is_object()) {
    s << v["counts"].value("error", 0) << " errors, " << v["counts"].value("warning", 0)
      << " warnings, " << v["counts"].value("info", 0) << " notes";
  }
  s << " over " << v.value("frames", 0) << " frames</p>";
  s << "<table class=\"findings\"><tr><th>check</th><th>severity</th>"
       "<th>count</th><th>where</th><th>what</th></tr>";
  bool any = false;
  if (v.contains("checks") && v["checks"].is_array()) {
    for (const nlohmann::json& check : v["checks"]) {
      const int64_t count = check.value("count", int64_t{0});
      if (count == 0) continue;
      any = true;
      const nlohmann::json findings = check.value("findings", nlohmann::json::array());
      s << "<tr class=\"" << HtmlEscape(check.value("severity", "")) << "\"><td>"
        << HtmlEscape(check.value("id", "")) << "</td><td>"
        << HtmlEscape(check.value("severity", "")) << "</td><td>" << count
        << "</td><td colspan=\"2\">"
        << (findings.size() < size_t(count)
                ? "the first " + std::to_string(findings.size()) + " listed"
                : "")
        << "</td></tr>";
      for (const nlohmann::json& f : findings) {
        const nlohmann::json location = f.value("location", nlohmann::json::object());
        std::string where = HtmlEscape(location.value("file", ""));
        if (location.contains("json_pointer")) {
          where += "#" + HtmlEscape(location["json_pointer"].get<std::string>());
        }
        if (location.contains("frame") && location["frame"].is_number_integer()) {
          const int64_t frame = location["frame"].get<int64_t>();
          const std::string label = "frame " + std::to_string(frame);
          where += " " + (on_sheet.count(frame)
                              ? "<a href=\"#frame-" + std::to_string(frame) + "\" data-goto=\"" +
                                    std::to_string(frame) + "\">" + label + "</a>"
                              : label);
        }
        if (location.contains("pixel") && location["pixel"].is_array() &&
            location["pixel"].size() == 2) {
          where +=
              " pixel (" + location["pixel"][0].dump() + ", " + location["pixel"][1].dump() + ")";
        }
        s << "<tr class=\"finding\"><td></td><td>" << HtmlEscape(f.value("severity", ""))
          << "</td><td></td><td>" << where << "</td><td>"
          << HtmlEscape(
                 (f.contains("object") ? f["object"].get<std::string>() + ": " : std::string()) +
                 f.value("message", ""))
          << "</td></tr>";
      }
    }
  }
  if (!any) s << "<tr><td colspan=\"5\">no findings</td></tr>";
  s << "</table></section>";
  return s.str();
}

}  // namespace lsds::report
