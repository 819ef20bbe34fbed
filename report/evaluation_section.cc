#include "report/evaluation_section.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "libs/collection/schema.h"
#include "libs/util/error.h"

namespace lsds::report {

using nlohmann::json;

namespace {

std::string Number(const json& value, const char* format = "%.3f") {
  if (!value.is_number()) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), format, value.get<double>());
  return buffer;
}

// COCOeval's 12 numbers in summarize()'s order.
void CocoTable(const json& coco, Html* out) {
  static const char* const kNames[] = {
      "AP", "AP50", "AP75", "APs", "APm", "APl", "AR1", "AR10", "AR100", "ARs", "ARm", "ARl"};
  *out << "<table class=\"coco\"><tr>";
  for (const char* name : kNames) *out << "<th>" << std::string(name) << "</th>";
  *out << "</tr><tr>";
  for (const char* name : kNames) *out << "<td>" << Number(coco.value(name, json())) << "</td>";
  *out << "</tr></table>";
}

void DotaTable(const json& dota, Html* out) {
  *out << "<p>DOTA task 1, VOC AP " << dota["ap"].get<std::string>() << ", polygon IoU &gt; "
       << Number(dota["iou_threshold"], "%g") << ": mAP " << Number(dota["mAP"], "%.4f")
       << "</p><table class=\"dota\"><tr><th>class</th><th>objects</th><th>difficult</th>"
          "<th>detections</th><th>true positives</th><th>AP</th></tr>";
  for (const json& c : dota["classes"]) {
    *out << "<tr><td>" << c["name"].get<std::string>() << "</td><td>" << c["objects"].get<int64_t>()
         << "</td><td>" << c["difficult"].get<int64_t>() << "</td><td>"
         << c["detections"].get<int64_t>() << "</td><td>" << c["true_positives"].get<int64_t>()
         << "</td><td>" << Number(c["AP"], "%.4f") << "</td></tr>";
  }
  *out << "</table>";
}

// Each condition's worst stratum (its first: lsds evaluate ranks them worst
// first), the conditions ordered by that stratum's recall at IoU .5.
void WorstStrata(const json& conditions, Html* out) {
  std::vector<std::pair<const json*, const json*>> worst;
  for (const json& c : conditions)
    if (!c["strata"].empty()) worst.emplace_back(&c, &c["strata"][0]);
  std::stable_sort(worst.begin(), worst.end(), [](const auto& a, const auto& b) {
    return (*a.second)["recall_50"].template get<double>() <
           (*b.second)["recall_50"].template get<double>();
  });
  *out << "<h3>Worst stratum of each condition</h3><table class=\"strata\"><tr><th>condition</th>"
          "<th>stratum</th><th>objects</th><th>frames</th><th>AP</th><th>AP50</th>"
          "<th>recall@.5</th><th>95% Wilson</th></tr>";
  for (const auto& [condition, s] : worst) {
    const json& ci = (*s)["recall_50_ci"];
    if ((*s)["thin"].get<bool>()) {
      *out << "<tr class=\"thin\"><td>";
    } else {
      *out << "<tr><td>";
    }
    *out << (*condition)["name"].get<std::string>() << "</td><td>"
         << (*s)["label"].get<std::string>() << "</td><td>" << (*s)["objects"].get<int64_t>()
         << "</td><td>" << (*s)["frames"].get<int64_t>() << "</td><td>" << Number((*s)["AP"])
         << "</td><td>" << Number((*s)["AP50"]) << "</td><td>" << Number((*s)["recall_50"])
         << "</td><td>[" << Number(ci[0]) << ", " << Number(ci[1]) << "]</td></tr>";
  }
  *out << "</table>";
}

void CoverageHoles(const json& coverage, Html* out) {
  *out << "<h3>Coverage</h3><table class=\"coverage\"><tr><th>condition</th><th>empty cells</th>"
          "<th>thin cells</th></tr>";
  for (const json& c : coverage) {
    std::string empty, thin;
    for (const json& cell : c["cells"]) {
      const json& flag = cell["flag"];
      if (!flag.is_string()) continue;
      std::string& list = flag == "empty" ? empty : thin;
      list += (list.empty() ? "" : ", ") + cell["label"].get<std::string>();
    }
    *out << "<tr><td>" << c["name"].get<std::string>() << "</td><td>"
         << (empty.empty() ? "-" : empty) << "</td><td>" << (thin.empty() ? "-" : thin)
         << "</td></tr>";
  }
  *out << "</table>";
}

}  // namespace

void CheckEvaluation(const json& evaluation, const std::string& file) {
  if (!evaluation.is_object() || evaluation.value("format", json()) != "lsds-evaluation")
    throw Error(
        "not an lsds evaluate report (format lsds-evaluation; write one with lsds evaluate -o)",
        Location(file, "/format"));
  JsonSchema::Get("evaluate.schema.json").ValidateOrThrow(evaluation, file);
}

Html EvaluationSection(const json& evaluation) {
  Html out;
  out << "<section id=\"evaluation\"><h2>Evaluation</h2><p class=\"help\">From <code>lsds "
         "evaluate</code> (docs/evaluate.md): ";
  if (evaluation["predictions"].is_string()) {
    out << "predictions " << evaluation["predictions"].get<std::string>() << ", "
        << evaluation.value("detections", int64_t{0}) << " detections, IoU "
        << evaluation["options"].value("iou_type", std::string("bbox")) << "; ";
  } else {
    out << "coverage only; ";
  }
  out << evaluation["ground_truth"]["images"].get<int64_t>() << " images, "
      << evaluation["ground_truth"]["annotations"].get<int64_t>() << " objects. Thin: fewer than "
      << evaluation["options"]["thin_below"].get<int64_t>()
      << " objects (frames for a frame condition).</p>";
  if (evaluation.contains("coco")) CocoTable(evaluation["coco"], &out);
  if (evaluation.contains("dota")) DotaTable(evaluation["dota"], &out);
  if (evaluation.contains("conditions")) WorstStrata(evaluation["conditions"], &out);
  CoverageHoles(evaluation["coverage"], &out);
  out << "</section>";
  return out;
}

}  // namespace lsds::report
