#include "evaluate/evaluate_report.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "converters/format_util.h"
#include "libs/util/error.h"
#include "libs/util/junit.h"
#include "libs/util/strings.h"

namespace lsds::evaluate {

using nlohmann::json;

namespace {

using convert::Format;

const char* LevelName(Level level) { return level == Level::kObject ? "object" : "frame"; }

json StratumJson(const StratumMetrics& s) {
  return {{"label", s.label},
          {"objects", s.objects},
          {"frames", s.frames},
          {"matched_50", s.matched_50},
          {"false_positives_50", s.false_positives_50},
          {"AP", s.ap},
          {"AP50", s.ap50},
          {"AR100", s.ar100},
          {"recall_50", s.recall_50},
          {"recall_50_ci", {s.recall_50_ci.low, s.recall_50_ci.high}},
          {"thin", s.thin}};
}

json CoverageJson(const ConditionCoverage& c) {
  json cells = json::array();
  for (const CoverageCell& cell : c.cells) {
    cells.push_back({{"label", cell.label},
                     {"objects", cell.objects},
                     {"frames", cell.frames},
                     {"flag", cell.flag.empty() ? json() : json(cell.flag)}});
    if (cell.planned >= 0) cells.back()["planned"] = cell.planned;
  }
  return {{"name", c.name},
          {"description", c.description},
          {"level", LevelName(c.level)},
          {"unrecorded", c.unrecorded},
          {"cells", std::move(cells)}};
}

// pycocotools' summary lines (cocoeval.py:429-456).
std::string CocoLines(const CocoStats& stats) {
  struct Line {
    bool ap;
    const char* iou;
    const char* area;
    int max_dets;
  };
  const Line lines[12] = {{true, "0.50:0.95", "all", 100},
                          {true, "0.50", "all", 100},
                          {true, "0.75", "all", 100},
                          {true, "0.50:0.95", "small", 100},
                          {true, "0.50:0.95", "medium", 100},
                          {true, "0.50:0.95", "large", 100},
                          {false, "0.50:0.95", "all", 1},
                          {false, "0.50:0.95", "all", 10},
                          {false, "0.50:0.95", "all", 100},
                          {false, "0.50:0.95", "small", 100},
                          {false, "0.50:0.95", "medium", 100},
                          {false, "0.50:0.95", "large", 100}};
  std::string out;
  for (int i = 0; i < 12; ++i) {
    const Line& l = lines[i];
    out += Format(" %-18s %s @[ IoU=%-9s | area=%6s | maxDets=%3d ] = %0.3f\n",
                  l.ap ? "Average Precision" : "Average Recall",
                  l.ap ? "(AP)" : "(AR)",
                  l.iou,
                  l.area,
                  l.max_dets,
                  stats[i]);
  }
  return out;
}

std::string StrataText(const ConditionMetrics& c) {
  std::string out = c.name + " (" + c.description + "), worst first:\n";
  out += Format("  %-24s %8s %7s %7s %7s %7s  %s\n",
                "stratum",
                "objects",
                "frames",
                "AP",
                "AP50",
                "AR100",
                "recall@.5 [95% Wilson]");
  for (const StratumMetrics& s : c.strata) {
    out += Format("  %-24s %8lld %7lld %7.3f %7.3f %7.3f  %.3f [%.3f, %.3f]%s\n",
                  s.label.c_str(),
                  static_cast<long long>(s.objects),
                  static_cast<long long>(s.frames),
                  s.ap,
                  s.ap50,
                  s.ar100,
                  s.recall_50,
                  s.recall_50_ci.low,
                  s.recall_50_ci.high,
                  s.thin ? "  thin" : "");
  }
  return out;
}

std::string CoverageText(const ConditionCoverage& c) {
  std::string out = c.name + " (" + c.description + ")";
  if (c.unrecorded > 0)
    out += Format(", not recorded for %lld %s",
                  static_cast<long long>(c.unrecorded),
                  c.level == Level::kObject ? "objects" : "frames");
  out += ":\n";
  for (const CoverageCell& cell : c.cells) {
    const std::string planned =
        cell.planned >= 0 ? Format("  planned %6lld", static_cast<long long>(cell.planned)) : "";
    out += Format("  %-24s objects %7lld  frames %6lld%s  %s\n",
                  cell.label.c_str(),
                  static_cast<long long>(cell.objects),
                  static_cast<long long>(cell.frames),
                  planned.c_str(),
                  cell.flag.c_str());
  }
  return out;
}

}  // namespace

Threshold ParseThreshold(const std::string& text) {
  const size_t eq = text.find('=');
  Threshold t;
  t.metric = text.substr(0, eq);
  bool known = false;
  std::vector<std::string> names;
  for (const char* name : CocoStatNames()) {
    names.emplace_back(name);
    known = known || t.metric == name;
  }
  if (eq == std::string::npos || !known) {
    throw Error("--fail-under " + text + ": expected METRIC=VALUE with METRIC one of " +
                Join(names, ", ") + (eq == std::string::npos ? "" : DidYouMean(t.metric, names)));
  }
  const std::string value = text.substr(eq + 1);
  char* end = nullptr;
  t.value = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(t.value))
    throw Error("--fail-under " + text + ": '" + value + "' is not a finite number");
  return t;
}

bool CheckThresholds(const CocoStats& stats, std::vector<Threshold>* thresholds) {
  bool all = true;
  for (Threshold& t : *thresholds) {
    for (size_t i = 0; i < stats.size(); ++i)
      if (t.metric == CocoStatNames()[i]) t.actual = stats[i];
    t.passed = !(t.actual < t.value);
    all = all && t.passed;
  }
  return all;
}

namespace {

const char* VocApName(VocAp ap) { return ap == VocAp::k07 ? "voc07" : "voc12"; }

json DotaJson(const DotaResult& dota) {
  json classes = json::array();
  for (const DotaClassResult& c : dota.classes) {
    classes.push_back({{"name", c.class_name},
                       {"objects", c.objects},
                       {"difficult", c.difficult},
                       {"detections", c.detections},
                       {"true_positives", c.true_positives},
                       {"AP", c.ap ? json(*c.ap) : json()}});
  }
  return {{"ap", VocApName(dota.ap)},
          {"iou_threshold", dota.iou_threshold},
          {"mAP", dota.map ? json(*dota.map) : json()},
          {"classes", std::move(classes)}};
}

std::string DotaText(const DotaResult& dota) {
  std::string out = Format("DOTA task 1 (oriented boxes, polygon IoU > %g, VOC AP %s):\n",
                           dota.iou_threshold,
                           dota.ap == VocAp::k07 ? "07, 11 points" : "10-12, area");
  out += "  class                     objects  difficult  detections  true pos.      AP\n";
  for (const DotaClassResult& c : dota.classes) {
    out += Format("  %-24s %8lld %10lld %11lld %10lld  %s\n",
                  c.class_name.c_str(),
                  static_cast<long long>(c.objects),
                  static_cast<long long>(c.difficult),
                  static_cast<long long>(c.detections),
                  static_cast<long long>(c.true_positives),
                  c.ap ? Format("%.4f", *c.ap).c_str() : "-");
  }
  out += dota.map ? Format("mAP = %.4f\n", *dota.map) : std::string("mAP: no class has objects\n");
  return out;
}

}  // namespace

json ReportJson(const EvaluationReport& report) {
  json categories = json::array();
  for (const auto& [id, name] : report.categories)
    categories.push_back({{"id", id}, {"name", name}});
  json doc = {{"format", "lsds-evaluation"},
              {"format_version", "1.0"},
              {"collection", report.collection},
              {"predictions", report.predictions ? json(*report.predictions) : json()},
              {"ground_truth",
               {{"images", report.images},
                {"annotations", report.annotations},
                {"categories", std::move(categories)}}},
              {"options", {{"thin_below", report.thin_below}, {"interval", "wilson-95"}}}};
  json coverage = json::array();
  for (const ConditionCoverage& c : report.coverage) coverage.push_back(CoverageJson(c));
  doc["coverage"] = std::move(coverage);
  if (report.dota) {
    doc["detections"] = report.detections;
    doc["options"]["iou_type"] = "obb";
    doc["dota"] = DotaJson(*report.dota);
  }
  if (!report.stats) return doc;
  json coco = json::object();
  for (size_t i = 0; i < report.stats->size(); ++i) coco[CocoStatNames()[i]] = (*report.stats)[i];
  doc["detections"] = report.detections;
  doc["options"]["iou_type"] = report.iou_type;
  doc["coco"] = std::move(coco);
  doc["counts"] = {{"objects", report.all.ground_truth},
                   {"matched_50", report.all.matched_50},
                   {"false_positives_50", report.all.false_positives_50}};
  json conditions = json::array();
  for (const ConditionMetrics& c : report.strata) {
    json strata = json::array();
    for (const StratumMetrics& s : c.strata) strata.push_back(StratumJson(s));
    conditions.push_back({{"name", c.name},
                          {"description", c.description},
                          {"level", LevelName(c.level)},
                          {"strata", std::move(strata)}});
  }
  doc["conditions"] = std::move(conditions);
  json thresholds = json::array();
  for (const Threshold& t : report.thresholds)
    thresholds.push_back(
        {{"metric", t.metric}, {"value", t.value}, {"actual", t.actual}, {"passed", t.passed}});
  doc["thresholds"] = std::move(thresholds);
  return doc;
}

std::string ReportText(const EvaluationReport& report) {
  std::string out = Format("ground truth: %lld images, %lld boxes, %zu categories\n",
                           static_cast<long long>(report.images),
                           static_cast<long long>(report.annotations),
                           report.categories.size());
  if (!report.stats) {
    out += "coverage (cells with fewer than " + std::to_string(report.thin_below) +
           " objects, or frames for a frame condition, are thin):\n";
    for (const ConditionCoverage& c : report.coverage) out += CoverageText(c);
    return out;
  }
  out += Format("predictions: %lld detections, IoU of %s\n",
                static_cast<long long>(report.detections),
                report.iou_type == "segm"  ? "masks (iouType segm)"
                : report.iou_type == "obb" ? "oriented boxes (polygon IoU, COCO's rules)"
                                           : "boxes (iouType bbox)");
  if (report.dota) out += DotaText(*report.dota);
  out += CocoLines(*report.stats);
  out += Format("objects %lld, matched at IoU .5: %lld, false positives at IoU .5: %lld\n",
                static_cast<long long>(report.all.ground_truth),
                static_cast<long long>(report.all.matched_50),
                static_cast<long long>(report.all.false_positives_50));
  for (const ConditionMetrics& c : report.strata) out += StrataText(c);
  for (const Threshold& t : report.thresholds) {
    out += Format("%s %s = %.6g (--fail-under %s=%g)\n",
                  t.passed ? "pass" : "FAIL",
                  t.metric.c_str(),
                  t.actual,
                  t.metric.c_str(),
                  t.value);
  }
  return out;
}

std::string ReportJUnit(const EvaluationReport& report) {
  JUnitSuite suite;
  suite.suites_name = "lsds evaluate";
  suite.name = report.collection;
  suite.time = "0";
  for (const Threshold& t : report.thresholds) {
    JUnitCase c;
    c.classname = "evaluate.fail-under";
    c.name = t.metric + " >= " + FormatNumber(t.value);
    c.time = "0";
    if (!t.passed) {
      c.outcome = JUnitCase::Outcome::kFailure;
      c.failure_type = "threshold";
      c.failure_message =
          t.metric + " = " + FormatNumber(t.actual) + " is under " + FormatNumber(t.value);
      c.body = c.failure_message;
    }
    suite.cases.push_back(std::move(c));
  }
  JUnitCase summary;
  summary.classname = "evaluate";
  summary.name = report.stats ? "metrics" : "coverage";
  summary.time = "0";
  summary.outcome = JUnitCase::Outcome::kOutput;
  summary.body = ReportText(report);
  suite.cases.push_back(std::move(summary));
  return JUnitXml(suite);
}

}  // namespace lsds::evaluate
