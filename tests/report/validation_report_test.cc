// The page's text safety and the typed reading of validation reports: every
// string from an input reaches the page escaped (Html), and every malformed
// value of a validation report is an lsds::Error at its JSON pointer, never an
// internal error.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/util/error.h"
#include "report/html_text.h"
#include "report/validation_section.h"

namespace lsds::report {
namespace {

using nlohmann::json;

const std::string kScript = "<script>document.title='PWNED'</script>";
const std::string kImg = "<img src=x onerror=\"document.title='PWNED'\">";
const std::string kAttribute = "\" onmouseover=\"alert(1)\" x='";

TEST(Html, LiteralsAreMarkupEverythingElseIsText) {
  Html html;
  const std::string text = kScript;
  const char* pointer = "<b>";
  html << "<p class=\"x\">" << text << pointer << std::string_view("&") << 42 << " " << -7 << " "
       << 2.5 << " " << uint64_t{18446744073709551615u} << "</p>";
  EXPECT_EQ(html.str(),
            "<p class=\"x\">&lt;script&gt;document.title=&apos;PWNED&apos;&lt;/script&gt;"
            "&lt;b&gt;&amp;42 -7 2.5 18446744073709551615</p>");
  EXPECT_EQ(Html::Text(kImg).str(),
            "&lt;img src=x onerror=&quot;document.title=&apos;PWNED&apos;&quot;&gt;");
  EXPECT_EQ(Html::Markup("<br>").str(), "<br>");
  // Nested pieces keep what they are.
  Html outer;
  outer << "<div>" << Html::Text("</div>") << Html::Markup("<hr>") << "</div>";
  EXPECT_EQ(outer.str(), "<div>&lt;/div&gt;<hr></div>");
  // Control characters XML forbids become spaces; UTF-8 passes.
  EXPECT_EQ(HtmlEscape(std::string("a\x01"
                                   "b\tc\xc3\xa9",
                                   7)),
            "a b\tc\xc3\xa9");
}

// A well-formed report whose every free-text field holds `payload`.
json Report(const std::string& payload) {
  return json::parse(R"({"format": "lsds-validate-report", "format_version": "1.0",
    "collection": "c", "verdict": "fail", "fail_on": "error", "frames": 12,
    "files_decoded": 0, "bytes_decoded": 0, "seconds": 0,
    "counts": {"error": 2, "warning": 0, "info": 0},
    "checks": [{"id": "layer.depth-finite", "severity": "error", "tolerance": "",
      "count": 3, "findings": [{"severity": "error", "check": "layer.depth-finite",
      "object": "o", "location": {"file": "f", "json_pointer": "/p", "frame": 7,
      "pixel": [3, 4], "line": 2, "column": 5}, "message": "m"}]}],
    "statistics": {}})")
      .patch(json::array({
          {{"op", "replace"}, {"path", "/collection"}, {"value", payload}},
          {{"op", "replace"}, {"path", "/checks/0/tolerance"}, {"value", payload}},
          {{"op", "replace"}, {"path", "/checks/0/findings/0/check"}, {"value", payload}},
          {{"op", "replace"}, {"path", "/checks/0/findings/0/object"}, {"value", payload}},
          {{"op", "replace"}, {"path", "/checks/0/findings/0/message"}, {"value", payload}},
          {{"op", "replace"}, {"path", "/checks/0/findings/0/location/file"}, {"value", payload}},
          {{"op", "replace"},
           {"path", "/checks/0/findings/0/location/json_pointer"},
           {"value", payload}},
      }));
}

TEST(ValidationSection, EveryStringIsTextOnThePage) {
  for (const std::string& payload : {kScript, kImg, kAttribute}) {
    const ValidationSummary v = ReadValidationReport(Report(payload), "v.json");
    ASSERT_EQ(v.checks.size(), 1u);
    const ValidationFinding& f = v.checks[0].findings.at(0);
    EXPECT_EQ(f.object, payload);
    EXPECT_EQ(f.file, payload);
    ASSERT_TRUE(f.pixel.has_value());
    EXPECT_EQ((*f.pixel)[0], 3);
    const std::string html = ValidationSection(v, {7}).str();
    EXPECT_EQ(html.find(payload), std::string::npos) << html;
    EXPECT_EQ(html.find("<script"), std::string::npos);
    EXPECT_EQ(html.find("<img"), std::string::npos);
    EXPECT_EQ(html.find("\" onmouseover"), std::string::npos);
    // Shown, as text: object, message, file and pointer.
    const std::string text = HtmlEscape(payload);
    EXPECT_NE(html.find(text + ": " + text + "</td>"), std::string::npos) << html;
    EXPECT_NE(html.find(text + ":2:5#" + text +
                        " <a href=\"#frame-7\" data-goto=\"7\">frame 7</a>"
                        " pixel (3, 4)"),
              std::string::npos)
        << html;
    EXPECT_NE(html.find("fail (fail on error): 2 errors, 0 warnings, 0 notes over 12 frames"),
              std::string::npos);
    EXPECT_NE(html.find("the first 1 listed"), std::string::npos);
  }
  // A frame not on the contact sheet is named, not linked.
  const std::string html = ValidationSection(ReadValidationReport(Report("x"), "v.json"), {}).str();
  EXPECT_EQ(html.find("<a href"), std::string::npos);
  EXPECT_NE(html.find(" frame 7 pixel (3, 4)"), std::string::npos);
}

struct Malformed {
  std::string path;   // JSON pointer of the value replaced
  json value;         // the replacement
  std::string where;  // the JSON pointer the error must name
};

TEST(ValidationReport, EveryMalformedValueIsAnErrorAtItsPointer) {
  const std::string finding = "/checks/0/findings/0";
  const std::vector<Malformed> cases = {
      {"/format", 1, "/format"},
      {"/format", "lsds-bundle-stats", "/format"},
      {"/verdict", 5, "/verdict"},
      {"/verdict", kScript, "/verdict"},
      {"/fail_on", json::object(), "/fail_on"},
      {"/frames", "12", "/frames"},
      {"/frames", true, "/frames"},
      {"/counts", json::array(), "/counts"},
      {"/counts/error", "2", "/counts/error"},
      {"/counts/warning", 1.5, "/counts/warning"},
      {"/checks", json::object(), "/checks"},
      {"/checks/0", "check", "/checks/0"},
      {"/checks/0/id", kScript, "/checks/0/id"},
      {"/checks/0/id", 3, "/checks/0/id"},
      {"/checks/0/severity", json::array(), "/checks/0/severity"},
      {"/checks/0/count", "3", "/checks/0/count"},
      {"/checks/0/count", json::object(), "/checks/0/count"},
      {"/checks/0/findings", "none", "/checks/0/findings"},
      {finding, 1, finding},
      {finding + "/severity", 2, finding + "/severity"},
      {finding + "/object", 7, finding + "/object"},
      {finding + "/message", nullptr, finding + "/message"},
      {finding + "/location", "f", finding + "/location"},
      {finding + "/location/file", json::array({1}), finding + "/location/file"},
      {finding + "/location/json_pointer", json::object(), finding + "/location/json_pointer"},
      {finding + "/location/frame", "7", finding + "/location/frame"},
      {finding + "/location/frame", 1.5, finding + "/location/frame"},
      {finding + "/location/frame",
       json(uint64_t{18446744073709551615u}),
       finding + "/location/frame"},
      {finding + "/location/pixel", "3, 4", finding + "/location/pixel"},
      {finding + "/location/pixel", json::array({3}), finding + "/location/pixel"},
      {finding + "/location/pixel", json::array({kScript, 4}), finding + "/location/pixel/0"},
      {finding + "/location/pixel",
       json::array({3, json::object()}),
       finding + "/location/pixel/1"},
      {finding + "/location/pixel",
       json::array({3, uint64_t{18446744073709551615u}}),
       finding + "/location/pixel/1"},
      {finding + "/location/line", "2", finding + "/location/line"},
  };
  for (const Malformed& c : cases) {
    json report = Report("x");
    report[json::json_pointer(c.path)] = c.value;
    try {
      (void)ReadValidationReport(report, "v.json");
      ADD_FAILURE() << c.path << " = " << c.value.dump() << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.location().file, "v.json") << c.path;
      EXPECT_EQ(e.location().json_pointer, c.where)
          << c.path << " = " << c.value.dump() << ": " << e.what();
    }
  }
  // Not an object at all.
  for (const json& document : {json::array(), json("report"), json(nullptr)}) {
    try {
      (void)ReadValidationReport(document, "v.json");
      ADD_FAILURE() << document.dump() << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.location().json_pointer, "/format");
    }
  }
}

TEST(ValidationReport, TextErrorsAreAtLineAndColumn) {
  try {
    (void)ParseValidationReport("{\"format\": \"lsds-validate-report\",\n  \"verdict\": }",
                                "v.json");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().file, "v.json");
    EXPECT_EQ(e.location().line, 2);
    EXPECT_GT(e.location().column, 0);
  }
  const std::string deep =
      "{\"checks\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  try {
    (void)ParseValidationReport(deep, "v.json");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nesting deeper"), std::string::npos) << e.what();
    EXPECT_EQ(e.location().line, 1);
  }
  // The well-formed text reads.
  EXPECT_EQ(ParseValidationReport(Report("x").dump(), "v.json").frames, 12);
}

TEST(ValidationReport, FramesWithFindingsInReportOrderUpToMax) {
  json report = Report("x");
  json& findings = report["checks"][0]["findings"];
  for (int frame : {9, 2, 9, 5}) {
    json f = findings[0];
    f["location"]["frame"] = frame;
    findings.push_back(f);
  }
  json no_frame = findings[0];
  no_frame["location"].erase("frame");
  findings.push_back(no_frame);
  report["checks"][0]["count"] = findings.size();
  const ValidationSummary v = ReadValidationReport(report, "v.json");
  EXPECT_EQ(FramesWithFindings(v, 12), (std::set<int64_t>{2, 5, 7, 9}));
  EXPECT_EQ(FramesWithFindings(v, 2), (std::set<int64_t>{7, 9}));
}

}  // namespace
}  // namespace lsds::report
