// End-to-end: `lsds report` as a user runs it, and the page as a browser shows
// it (headless Chromium: a screenshot that is not blank, no script errors).
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "report/html_text.h"
#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

using testing::RunCommandLine;
namespace fs = std::filesystem;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Every file of a folder with its content, to show that inputs stay untouched.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) {
      out[fs::relative(entry.path(), root).string()] = Slurp(entry.path());
    }
  }
  return out;
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class ReportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto synth = RunCommandLine(testing::LsdsBinary() + " synth " + (dir_ / "c").string() +
                                      " --count 12 --size 160x120");
    ASSERT_EQ(synth.exit_code, 0) << synth.output;
  }
  std::string Report(const std::string& args) {
    return testing::LsdsBinary() + " report " + (dir_ / "c").string() + " " + args;
  }
  testing::TempDir dir_;
};

TEST_F(ReportCli, WritesOnePageAndLeavesTheInputAlone) {
  const auto before = Snapshot(dir_ / "c");
  const fs::path page = dir_ / "report.html";
  const auto result =
      RunCommandLine(Report("-o " + page.string() + " --sample 5 --layer-frames 2 --validate"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(Snapshot(dir_ / "c"), before);
  const std::string html = Slurp(page);
  EXPECT_EQ(Count(html, "<figure class=\"card\""), 5u);
  EXPECT_EQ(Count(html, "<section class=\"layers\""), 2u);
  EXPECT_NE(html.find("id=\"validation\""), std::string::npos);
  EXPECT_NE(html.find("data-id=\"gsd\""), std::string::npos);
  // Self-contained: every image is inline, nothing is fetched.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("src=\"file"), std::string::npos);
  EXPECT_GT(Count(html, "src=\"data:image/"), 5u);
  // Only the temporary-free page is left beside it.
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_.path())) {
    files += entry.is_regular_file();
  }
  EXPECT_EQ(files, 1u);
}

TEST_F(ReportCli, RefusesExistingOutputAndOutputInsideTheCollection) {
  const fs::path page = dir_ / "report.html";
  ASSERT_EQ(RunCommandLine(Report("-o " + page.string())).exit_code, 0);
  const auto again = RunCommandLine(Report("-o " + page.string()));
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.output.find(page.string()), std::string::npos);
  EXPECT_EQ(RunCommandLine(Report("-o " + page.string() + " --force")).exit_code, 0);
  const auto inside = RunCommandLine(Report("-o " + (dir_ / "c" / "r.html").string()));
  EXPECT_EQ(inside.exit_code, 2);
  EXPECT_NE(inside.output.find("lies inside the collection folder"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "c" / "r.html"));
  const auto bad_range =
      RunCommandLine(Report("-o " + (dir_ / "x.html").string() + " --frames 99"));
  EXPECT_EQ(bad_range.exit_code, 2);
  EXPECT_NE(bad_range.output.find("--frames"), std::string::npos);
  const auto not_a_collection =
      RunCommandLine(testing::LsdsBinary() + " report " + dir_.path().string() + " -o " +
                     (dir_ / "y.html").string());
  EXPECT_EQ(not_a_collection.exit_code, 2);
  EXPECT_NE(not_a_collection.output.find("collection.json"), std::string::npos);
}

TEST_F(ReportCli, AnUnreadableLayerIsShownNotFatal) {
  // The page is for looking at broken collections too: a corrupt file becomes
  // a message naming it where its picture would be.
  std::ofstream(dir_ / "c" / "rgb" / "000000.exr") << "not an EXR";
  std::ofstream(dir_ / "c" / "depth" / "000000.exr") << "not an EXR";
  const fs::path page = dir_ / "report.html";
  const auto result =
      RunCommandLine(Report("-o " + page.string() + " --sample 12 --layer-frames 12"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string html = Slurp(page);
  EXPECT_EQ(Count(html, "<figure class=\"card\""), 12u);
  EXPECT_NE(html.find("cannot show rgb: " + (dir_ / "c" / "rgb" / "000000.exr").string()),
            std::string::npos);
  EXPECT_NE(html.find("cannot show depth: "), std::string::npos);
  // The terminal says so too, naming the first file.
  EXPECT_NE(result.output.find("warning: "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("could not be shown; the first: image of frame 0: " +
                               (dir_ / "c" / "rgb" / "000000.exr").string()),
            std::string::npos)
      << result.output;
  // Frame 0's altitude and GSD need its depth: unknown, not made up.
  const std::string card = html.substr(html.find("id=\"frame-0\""), 20000);
  EXPECT_NE(card.find("alt n/a"), std::string::npos);
  EXPECT_NE(card.find("GSD n/a"), std::string::npos);
}

TEST_F(ReportCli, FindingsLinkToTheirFrames) {
  // A validation report whose finding points at frame 7: the page links it and
  // puts frame 7 on the contact sheet even though the even spread would skip
  // it, within --sample: 2 frames, frame 7 and one other.
  const fs::path json = dir_ / "validation.json";
  std::ofstream(json) << R"({"format": "lsds-validate-report", "format_version": "1.0",
    "collection": "c", "verdict": "fail", "fail_on": "error", "frames": 12,
    "files_decoded": 0, "bytes_decoded": 0, "seconds": 0,
    "counts": {"error": 1, "warning": 0, "info": 0},
    "checks": [{"id": "layer.depth-finite", "severity": "error", "tolerance": "",
      "count": 1, "findings": [{"severity": "error", "check": "layer.depth-finite",
      "location": {"file": "depth/000007.exr", "frame": 7, "pixel": [3, 4]},
      "message": "depth is NaN"}]}],
    "statistics": {}})";
  const fs::path page = dir_ / "report.html";
  const auto result = RunCommandLine(
      Report("-o " + page.string() + " --sample 2 --validation-report " + json.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string html = Slurp(page);
  EXPECT_NE(html.find("<a href=\"#frame-7\""), std::string::npos);
  EXPECT_NE(html.find("id=\"frame-7\""), std::string::npos);
  EXPECT_EQ(Count(html, "<figure class=\"card\""), 2u);
  EXPECT_NE(html.find("depth is NaN"), std::string::npos);
}

TEST_F(ReportCli, BundleStatisticsFromLsdsBundles) {
  const fs::path stats = dir_ / "stats.json";
  const auto bundles = RunCommandLine(testing::LsdsBinary() + " bundles " + (dir_ / "c").string() +
                                      " -o " + stats.string());
  ASSERT_EQ(bundles.exit_code, 0) << bundles.output;
  const fs::path page = dir_ / "report.html";
  const auto result =
      RunCommandLine(Report("-o " + page.string() + " --bundle-stats " + stats.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string html = Slurp(page);
  ASSERT_NE(html.find("id=\"bundles\""), std::string::npos);
  // Every cell of the class-mixing matrix and every size band's counts, as
  // lsds bundles wrote them.
  const nlohmann::json json = nlohmann::json::parse(Slurp(stats));
  const nlohmann::json& mixing = json["summary"]["class_mixing"]["samples"];
  ASSERT_GE(mixing.size(), 2u);
  const std::string matrix = html.substr(html.find("class=\"mixing\""));
  size_t at = 0;
  for (const nlohmann::json& row : mixing) {
    for (const nlohmann::json& v : row) {
      at = matrix.find(">" + v.dump() + "<br>", at);
      ASSERT_NE(at, std::string::npos) << v;
    }
  }
  const std::string sizes = html.substr(html.find("class=\"sizes\""));
  at = 0;
  for (const nlohmann::json& band : json["summary"]["by_object_size"]) {
    at = sizes.find("<td>" + band["objects"].dump() + "</td><td>" + band["pixels"].dump() +
                        "</td><td>" + band["mixed_pixels"].dump() + "</td>",
                    at);
    ASSERT_NE(at, std::string::npos) << band;
  }
  // The page never replaces an input, even with --force.
  const auto same =
      RunCommandLine(Report("-o " + stats.string() + " --force --bundle-stats " + stats.string()));
  EXPECT_EQ(same.exit_code, 2);
  EXPECT_EQ(nlohmann::json::parse(Slurp(stats)), json);
  // Any other JSON file is refused, naming it.
  const fs::path other = dir_ / "c" / "collection.json";
  const auto bad = RunCommandLine(
      Report("-o " + (dir_ / "x.html").string() + " --bundle-stats " + other.string()));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find(other.string()), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "x.html"));
}

// The page in a real browser: a screenshot that is not blank, no console
// message, and the page script ran to its end with no error caught by its
// window.onerror hook. Skipped, saying why, when Chromium is absent
// (scripts/install-deps.sh installs it).
void CheckInChromium(const fs::path& page, const fs::path& scratch) {
  const std::string chromium =
      "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
      "--user-data-dir=" +
      (scratch / "profile").string() + " ";
  const fs::path shot = scratch / "shot.png";
  const auto screenshot = RunCommandLine(chromium +
                                         "--enable-logging=stderr --v=0 --window-size=1200,900 "
                                         "--screenshot=" +
                                         shot.string() + " file://" + page.string());
  ASSERT_TRUE(fs::exists(shot)) << screenshot.output;
  // Console messages from the page (the page itself logs nothing).
  const std::regex console(R"(CONSOLE[(:]\d+[)\]].*)");
  std::smatch match;
  EXPECT_FALSE(std::regex_search(screenshot.output, match, console)) << match.str();

  // Not blank: the contact sheet region (below the header) varies strongly.
  const cv::Mat image = cv::imread(shot.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  ASSERT_EQ(image.cols, 1200);
  const cv::Mat sheet = image(cv::Rect(0, 200, image.cols, image.rows - 200));
  cv::Scalar mean, stddev;
  cv::meanStdDev(sheet, mean, stddev);
  EXPECT_GT(stddev[0], 20.0) << "the page looks blank";

  const auto dom = RunCommandLine(chromium + "--dump-dom file://" + page.string());
  EXPECT_NE(dom.output.find("data-report-ready=\"1\""), std::string::npos)
      << dom.output.substr(0, 2000);
  EXPECT_EQ(dom.output.find("data-js-error=\""), std::string::npos);

  // Control: the same page with a failing script trips both probes.
  std::string broken = Slurp(page);
  broken.insert(broken.rfind("</body>"), "<script>no_such_function();</script>");
  const fs::path bad = scratch / "broken.html";
  std::ofstream(bad, std::ios::binary) << broken;
  const auto bad_dom = RunCommandLine(chromium +
                                      "--enable-logging=stderr --v=0 "
                                      "--dump-dom file://" +
                                      bad.string());
  EXPECT_NE(bad_dom.output.find("data-js-error=\""), std::string::npos);
  EXPECT_TRUE(std::regex_search(bad_dom.output, match, console));
}

bool HaveChromium() { return RunCommandLine("command -v chromium").exit_code == 0; }
constexpr const char* kNoChromium =
    "chromium is not installed (Debian package `chromium`, "
    "scripts/install-deps.sh): the page was not rendered";

// `lsds evaluate -o` of predictions (the truth converted by lsds convert --to
// yolo, every line given a confidence), shown as the page's evaluation section.
class ReportEvaluation : public ReportCli {
 protected:
  fs::path Evaluation() {
    const fs::path yolo = dir_ / "yolo";
    const auto convert =
        RunCommandLine(testing::LsdsBinary() + " convert " + (dir_ / "c").string() +
                       " --to yolo --images none -q -o " + yolo.string());
    EXPECT_EQ(convert.exit_code, 0) << convert.output;
    const fs::path predictions = dir_ / "predictions";
    fs::create_directories(predictions);
    for (const auto& entry : fs::directory_iterator(yolo / "labels" / "train")) {
      std::istringstream in(Slurp(entry.path()));
      std::ofstream out(predictions / entry.path().filename());
      for (std::string line; std::getline(in, line);) out << line << " 0.9\n";
    }
    const fs::path evaluation = dir_ / "eval.json";
    const auto evaluate = RunCommandLine(
        testing::LsdsBinary() + " evaluate " + (dir_ / "c").string() +
        " --format yolo -q --predictions " + predictions.string() + " -o " + evaluation.string());
    EXPECT_EQ(evaluate.exit_code, 0) << evaluate.output;
    return evaluation;
  }
};

TEST_F(ReportEvaluation, TheMetricsWorstStrataAndCoverageOfLsdsEvaluate) {
  const fs::path evaluation = Evaluation();
  const nlohmann::json json = nlohmann::json::parse(Slurp(evaluation));
  const fs::path page = dir_ / "report.html";
  const auto result =
      RunCommandLine(Report("-o " + page.string() + " --evaluation " + evaluation.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string html = Slurp(page);
  ASSERT_NE(html.find("<a href=\"#evaluation\">evaluation</a>"), std::string::npos);
  const std::string section = html.substr(html.find("<section id=\"evaluation\">"));
  // The 12 numbers as lsds evaluate computed them (every box found: AP 1).
  EXPECT_EQ(json["coco"]["AP"], 1.0);
  EXPECT_NE(section.find("<th>AP</th>"), std::string::npos);
  EXPECT_NE(section.find("<td>1.000</td>"), std::string::npos);
  // Each condition's worst stratum, with its counts.
  ASSERT_FALSE(json["conditions"].empty());
  for (const nlohmann::json& c : json["conditions"]) {
    if (c["strata"].empty()) continue;
    const nlohmann::json& worst = c["strata"][0];
    EXPECT_NE(
        section.find("<td>" + c["name"].get<std::string>() + "</td><td>" +
                     lsds::report::HtmlEscape(worst["label"].get<std::string>()) + "</td><td>" +
                     worst["objects"].dump() + "</td><td>" + worst["frames"].dump() + "</td>"),
        std::string::npos)
        << c["name"];
  }
  // Every coverage condition has its row.
  for (const nlohmann::json& c : json["coverage"])
    EXPECT_NE(section.find("<tr><td>" + c["name"].get<std::string>() + "</td>"), std::string::npos)
        << c["name"];
  // Any other JSON file is refused, naming it; nothing is written.
  const fs::path other = dir_ / "c" / "collection.json";
  const auto bad = RunCommandLine(
      Report("-o " + (dir_ / "x.html").string() + " --evaluation " + other.string()));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find(other.string()), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "x.html"));
}

TEST_F(ReportEvaluation, ChromiumShowsTheEvaluationSection) {
  if (!HaveChromium()) GTEST_SKIP() << kNoChromium;
  const fs::path evaluation = Evaluation();
  const fs::path page = dir_ / "report.html";
  ASSERT_EQ(RunCommandLine(
                Report("-o " + page.string() + " --sample 4 --evaluation " + evaluation.string()))
                .exit_code,
            0);
  CheckInChromium(page, dir_.path());
}

TEST_F(ReportCli, ChromiumShowsTheSynthReport) {
  if (!HaveChromium()) GTEST_SKIP() << kNoChromium;
  const fs::path page = dir_ / "report.html";
  ASSERT_EQ(
      RunCommandLine(Report("-o " + page.string() + " --sample 8 --layer-frames 2 --validate"))
          .exit_code,
      0);
  CheckInChromium(page, dir_.path());
}

// The page's interactivity, driven in the browser by a probe script appended
// to a copy of the page: the class filter hides and shows cards, clicking a
// card tagged "layers" opens its layers and objects.
TEST_F(ReportCli, ChromiumClassFilterAndFrameDetail) {
  if (!HaveChromium()) GTEST_SKIP() << kNoChromium;
  const fs::path page = dir_ / "report.html";
  ASSERT_EQ(
      RunCommandLine(Report("-o " + page.string() + " --sample 8 --layer-frames 2")).exit_code, 0);
  std::string html = Slurp(page);
  // Expected from the page's own data: cards without visible objects, cards
  // with a crate (class 3), and the first card tagged with layers.
  const std::regex card_re(R"re(id="frame-(\d+)" data-frame="\d+" data-classes="([^"]*)")re");
  int empty = 0, with_crate = 0, cards = 0, first_layers = -1;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), card_re);
       it != std::sregex_iterator();
       ++it, ++cards) {
    const std::string classes = (*it)[2];
    empty += classes.empty();
    with_crate += (" " + classes + " ").find(" c3 ") != std::string::npos;
    const size_t end = html.find("</figure>", it->position());
    if (first_layers < 0 &&
        html.substr(it->position(), end - it->position()).find("class=\"tag\"") !=
            std::string::npos)
      first_layers = cards;
  }
  ASSERT_EQ(cards, 8);
  ASSERT_GE(first_layers, 0);
  ASSERT_GT(with_crate, 0);
  html.insert(html.rfind("</body>"),
              R"(<script>
function shown(){return Array.prototype.filter.call(document.querySelectorAll('.card'),
  function(c){return c.style.display!=='none';}).length;}
function set(cls,on){var b=document.querySelector('.filter input[data-class="'+cls+'"]');
  b.checked=on;b.dispatchEvent(new Event('change'));}
var r=[];
set('c2',false);set('c3',false);r.push(shown());
set('c3',true);r.push(shown());
document.querySelectorAll('.card')[)" +
                  std::to_string(first_layers) + R"(].click();
var o=document.getElementById('overlay');
r.push(o.hidden?'hidden':'open');
r.push(o.querySelectorAll('table.objects').length);
r.push(o.querySelectorAll('.strip figure').length);
document.body.setAttribute('data-probe',r.join(','));
</script>)");
  const fs::path probe = dir_ / "probe.html";
  std::ofstream(probe, std::ios::binary) << html;
  const auto dom =
      RunCommandLine("chromium --headless --no-sandbox --disable-gpu --user-data-dir=" +
                     (dir_ / "profile").string() + " --dump-dom file://" + probe.string());
  // rgb, classid, instanceid, depth, normal, shadow, motion, bundle.
  const std::string expected =
      std::to_string(empty) + "," + std::to_string(with_crate) + ",open,1,8";
  EXPECT_NE(dom.output.find("data-probe=\"" + expected + "\""), std::string::npos)
      << "expected " << expected << " in " << dom.output.substr(0, dom.output.find("<header>"));
}

// The demo scene (`lsds generate --demo`, the scene of `make demo`) at a
// small size: rendered terrain, vegetation, targets, every layer and bundles.
TEST(ReportDemo, ChromiumShowsTheGeneratedDemoReport) {
  if (!HaveChromium()) GTEST_SKIP() << kNoChromium;
  testing::TempDir dir;
  const auto generate =
      RunCommandLine(testing::LsdsBinary() + " generate --demo --demo-frames 4 " +
                     "--demo-size 192x144 --spp 4 -q -o " + (dir / "demo").string());
  ASSERT_EQ(generate.exit_code, 0) << generate.output;
  const fs::path page = dir / "report.html";
  const auto report = RunCommandLine(testing::LsdsBinary() + " report " + (dir / "demo").string() +
                                     " -o " + page.string() + " --validate --layer-frames 1");
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string html = Slurp(page);
  EXPECT_EQ(Count(html, "<figure class=\"card\""), 4u);
  // Every layer the collection declares is pictured; the bundle as its
  // mixed-pixel map.
  const nlohmann::json collection = nlohmann::json::parse(Slurp(dir / "demo" / "collection.json"));
  for (const nlohmann::json& layer : collection["layers"]) {
    const std::string semantic = layer["semantic"];
    if (semantic == "worldposition" || semantic == "derived") continue;
    EXPECT_NE(html.find("<figcaption>" + layer["name"].get<std::string>()), std::string::npos)
        << semantic;
    if (semantic == "bundle") {
      EXPECT_NE(html.find("mixed pixels"), std::string::npos);
    }
  }
  CheckInChromium(page, dir.path());
}

// Script planted in every string of every input the report reads: the folder
// name, collection.json (provenance, class names, layer descriptions and
// units, metadata variants, sequences, scene state, object names, assets and
// materials), the perturbed metadata variant's file name and source, the
// validation report and the bundle statistics. In the page they are text: no element,
// attribute or script of theirs exists in the browser's DOM, the title stays
// the page's, and the payload is shown as text. A control page with the same
// payload inserted raw must trip the probe.
const std::string kPayload =
    "<script>document.title='PWNED'</script><img src=x onerror=\"document.title='PWNED'\">"
    "</style></title></textarea>\" onmouseover=\"document.title='PWNED'\" x='";
// Folder and file names cannot hold '/'.
const std::string kNamePayload = "<img src=x onerror=\"document.title='PWNED'\">";

// A shell word for any text (the folder name of this test holds quotes).
std::string Quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Every string value under `value`, except the members named in `keep`.
void PlantStrings(nlohmann::json* value,
                  const std::string& payload,
                  const std::set<std::string>& keep) {
  if (value->is_string()) {
    *value = payload;
  } else if (value->is_array()) {
    for (nlohmann::json& item : *value) PlantStrings(&item, payload, keep);
  } else if (value->is_object()) {
    for (auto& [key, member] : value->items()) {
      if (keep.count(key) == 0) PlantStrings(&member, payload, keep);
    }
  }
}

// How Chromium's --dump-dom serializes `text` in a text node.
std::string DomText(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&') {
      out += "&amp;";
    } else if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else {
      out += c;
    }
  }
  return out;
}

TEST(ReportHostile, ChromiumRunsNoScriptPlantedInAnyInput) {
  testing::TempDir dir;
  const fs::path c = dir / kNamePayload;
  const std::string lsds = testing::LsdsBinary() + " ";
  auto run = [&](const std::string& args) {
    const auto result = RunCommandLine(lsds + args);
    EXPECT_EQ(result.exit_code, 0) << args << "\n" << result.output;
  };
  run("synth " + Quote(c.string()) + " --count 6 --size 64x48");
  // A perturbed metadata variant, then given a hostile file name.
  run("perturb-metadata " + Quote(c.string()) + " --sigma 1 --seed 3 -o " +
      Quote((c / "m.json").string()));
  const fs::path stats = dir / "stats.json";
  run("bundles " + Quote(c.string()) + " -o " + Quote(stats.string()));
  ASSERT_FALSE(HasFailure());
  const std::string variant = kNamePayload + ".json";
  fs::rename(c / "m.json", c / variant);
  // The one free string of metadata.schema.json, in the variant the report
  // reads.
  nlohmann::json metadata = nlohmann::json::parse(Slurp(c / variant));
  metadata["source"] = kPayload;
  std::ofstream(c / variant, std::ios::binary) << metadata.dump(1);

  nlohmann::json collection = nlohmann::json::parse(Slurp(c / "collection.json"));
  nlohmann::json& provenance = collection["provenance"];
  provenance["generator"] = provenance["generator_version"] = kPayload;
  provenance["scene_source"] = provenance["capture_source"] = kPayload;
  provenance["render"] = {{"renderer", kPayload}};
  for (nlohmann::json& cls : collection["classes"]) {
    cls["name"] = kPayload + " " + cls["id"].dump();
  }
  for (nlohmann::json& layer : collection["layers"])
    layer["description"] = layer["unit"] = kPayload;
  for (nlohmann::json& metadata : collection["metadata"]) {
    metadata["description"] = kPayload;
    if (metadata["file"] == "m.json") metadata["file"] = variant;
  }
  for (nlohmann::json& frame : collection["frames"]) {
    frame["sequence"] = kPayload;
    frame["scene"] = {{"sky", {{"cloud_type", kPayload}}}, {"terrain_material", kPayload}};
    for (nlohmann::json& object : frame["objects"]) {
      object["name"] = object["asset"] = object["material"] = kPayload;
    }
  }
  std::ofstream(c / "collection.json", std::ios::binary) << collection.dump(1);

  nlohmann::json bundle_stats = nlohmann::json::parse(Slurp(stats));
  PlantStrings(&bundle_stats, kPayload, {"format", "format_version"});
  std::ofstream(stats, std::ios::binary) << bundle_stats.dump();

  // Every string the validation report schema leaves free.
  const fs::path validation = dir / "validation.json";
  nlohmann::json finding = {
      {"severity", "error"},
      {"check", kPayload},
      {"object", kPayload},
      {"message", kPayload},
      {"location",
       {{"file", kPayload}, {"json_pointer", kPayload}, {"frame", 1}, {"pixel", {3, 4}}}}};
  const nlohmann::json report = {
      {"format", "lsds-validate-report"},
      {"format_version", "1.0"},
      {"collection", kPayload},
      {"verdict", "fail"},
      {"fail_on", "error"},
      {"frames", 6},
      {"files_decoded", 0},
      {"bytes_decoded", 0},
      {"seconds", 0},
      {"counts", {{"error", 1}, {"warning", 0}, {"info", 0}}},
      {"checks",
       {{{"id", "layer.depth-finite"},
         {"severity", "error"},
         {"tolerance", kPayload},
         {"count", 1},
         {"findings", {finding}}}}},
      {"statistics", {{kPayload, {{"max", 1}, {"rms", 1}, {"count", 1}}}}}};
  std::ofstream(validation, std::ios::binary) << report.dump();

  const auto before = Snapshot(dir.path());
  const fs::path page = dir / "out" / "report.html";
  fs::create_directories(page.parent_path());
  const auto result =
      RunCommandLine(lsds + "report " + Quote(c.string()) + " -o " + Quote(page.string()) +
                     " --sample 6 --layer-frames 2" + " --validation-report " +
                     Quote(validation.string()) + " --bundle-stats " + Quote(stats.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(Snapshot(dir.path()).size(), before.size() + 1);
  for (const auto& [file, content] : before) {
    EXPECT_EQ(Slurp(dir / file), content) << file;
  }

  // The page as written: the payload only as escaped text, shown where each
  // planted field is shown.
  const std::string html = Slurp(page);
  EXPECT_EQ(html.find("<script>document.title"), std::string::npos);
  EXPECT_EQ(html.find("<img src=x"), std::string::npos);
  EXPECT_EQ(html.find("\" onmouseover"), std::string::npos);
  const std::string escaped = report::HtmlEscape(kPayload);
  // generator, version, class names (filter, histogram), sequences, cloud
  // types, object names, the finding's file, pointer, object and message, the
  // bundle layer: far more than 10.
  EXPECT_GT(Count(html, escaped), 10u);
  EXPECT_NE(html.find("<title>lsds report: " + report::HtmlEscape(kNamePayload) + "</title>"),
            std::string::npos);
  EXPECT_NE(html.find("variant " + report::HtmlEscape(variant) + "</p>"), std::string::npos);

  if (!HaveChromium()) GTEST_SKIP() << kNoChromium;
  // The virtual time budget lets a planted onerror or timer run before the
  // DOM is dumped.
  const std::string chromium =
      "chromium --headless --no-sandbox --disable-gpu --disable-background-networking "
      "--disable-component-update --disable-sync --no-first-run --virtual-time-budget=3000 "
      "--user-data-dir=" +
      Quote((dir / "profile").string()) + " --dump-dom ";
  const auto dom = RunCommandLine(chromium + Quote("file://" + page.string()));
  ASSERT_NE(dom.output.find("data-report-ready=\"1\""), std::string::npos)
      << dom.output.substr(0, 2000);
  EXPECT_EQ(dom.output.find("data-js-error=\""), std::string::npos);
  EXPECT_NE(dom.output.find("<title>lsds report: " + DomText(kNamePayload) + "</title>"),
            std::string::npos)
      << dom.output.substr(0, 2000);
  EXPECT_EQ(dom.output.find("PWNED</title>"), std::string::npos);
  EXPECT_EQ(dom.output.find("<img src=\"x\""), std::string::npos);
  EXPECT_EQ(dom.output.find("<script>document.title"), std::string::npos);
  EXPECT_GT(Count(dom.output, DomText(kPayload)), 10u);

  // Control: the payload inserted raw runs, and the probe sees it.
  std::string raw = html;
  raw.insert(raw.rfind("</body>"), kPayload);
  const fs::path control = dir / "out" / "control.html";
  std::ofstream(control, std::ios::binary) << raw;
  const auto bad = RunCommandLine(chromium + Quote("file://" + control.string()));
  EXPECT_NE(bad.output.find("<title>PWNED</title>"), std::string::npos)
      << bad.output.substr(0, 2000);
  EXPECT_NE(bad.output.find("<img src=\"x\""), std::string::npos);
}

}  // namespace
}  // namespace lsds
