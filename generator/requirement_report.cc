#include "generator/requirement_report.h"

#include <sstream>

#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

std::string List(const std::vector<int64_t>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + std::to_string(v[i]);
  return s + "]";
}

}  // namespace

void AddRequirementSummary(const Plan& plan, const Frame& truth, RequirementSummary* summary) {
  if (plan.requirements.is_null()) return;
  const nlohmann::json& quotas = plan.requirements.at("quotas");
  if (summary->achieved.empty())
    for (const nlohmann::json& q : quotas)
      summary->achieved.push_back(
          {q.at("name").get<std::string>(), std::vector<int64_t>(q.at("weights").size() + 1, 0)});
  if (truth.requirements.is_null()) return;
  const nlohmann::json& r = truth.requirements;
  ++summary->frames;
  summary->attempts += r.value("attempts", 1);
  if (r.value("met", false)) ++summary->estimate_met;
  if (r.value("achieved_met", false))
    ++summary->achieved_met;
  else
    summary->missed.push_back(truth.index);
  // A quota's achieved bin: where the achieved value of the frame's check
  // falls (the last slot counts values outside every bin, or not measured).
  for (size_t q = 0; q < quotas.size(); ++q) {
    const std::string name = quotas[q].at("name").get<std::string>();
    const std::vector<double> edges = quotas[q].at("bins").get<std::vector<double>>();
    for (const nlohmann::json& check : r.at("checks")) {
      if (check.at("name").get<std::string>() != name) continue;
      size_t bin = edges.size() - 1;  // "no bin"
      if (check.contains("achieved")) {
        const double v = check.at("achieved").get<double>();
        for (size_t b = 0; b + 1 < edges.size(); ++b)
          if (v >= edges[b] && (v < edges[b + 1] || (b + 2 == edges.size() && v <= edges[b + 1])))
            bin = b;
      }
      ++summary->achieved[q].second[bin];
      break;  // one check per quota and frame
    }
  }
}

std::string FormatPlannedRequirements(const Plan& plan) {
  if (plan.requirements.is_null()) return "";
  // Count the plan's frames as if their estimates were the truth.
  RequirementSummary summary;
  for (const PlannedFrame& f : plan.frames) {
    Frame truth;
    truth.index = f.index;
    if (f.requirements) {
      truth.requirements = *f.requirements;
      for (nlohmann::json& check : truth.requirements["checks"])
        if (check.contains("estimate")) check["achieved"] = check["estimate"];
      truth.requirements["achieved_met"] = truth.requirements.value("met", false);
    }
    AddRequirementSummary(plan, truth, &summary);
  }
  std::ostringstream out;
  out << "requirements: " << summary.frames << " frames with a demand, " << summary.estimate_met
      << " met by estimate in " << summary.attempts << " draws";
  if (!summary.missed.empty()) out << "; budget ran out on frames " << List(summary.missed);
  out << "\n";
  const nlohmann::json& quotas = plan.requirements.at("quotas");
  for (size_t q = 0; q < quotas.size() && q < summary.achieved.size(); ++q) {
    std::vector<int64_t> estimated = summary.achieved[q].second;
    estimated.pop_back();
    out << "quota " << summary.achieved[q].first << " "
        << quotas[q].at("quantity").get<std::string>() << " bins " << quotas[q].at("bins").dump()
        << ": planned " << List(quotas[q].at("planned").get<std::vector<int64_t>>())
        << " estimated " << List(estimated) << "\n";
  }
  return out.str();
}

std::string FormatRequirementSummary(const Plan& plan, const RequirementSummary& summary) {
  if (plan.requirements.is_null()) return "";
  std::ostringstream out;
  out << "requirements: " << summary.frames << " frames with a demand, " << summary.estimate_met
      << " met by estimate, " << summary.achieved_met << " met in the rendered truth, "
      << FormatNumber(summary.frames ? static_cast<double>(summary.frames) / summary.attempts : 1.0)
      << " draws accepted per draw estimated";
  if (!summary.missed.empty()) out << "; missed frames " << List(summary.missed);
  out << "\n";
  const nlohmann::json& quotas = plan.requirements.at("quotas");
  for (size_t q = 0; q < quotas.size() && q < summary.achieved.size(); ++q) {
    std::vector<int64_t> achieved = summary.achieved[q].second;
    const int64_t outside = achieved.back();
    achieved.pop_back();
    out << "quota " << summary.achieved[q].first << " "
        << quotas[q].at("quantity").get<std::string>() << " bins " << quotas[q].at("bins").dump()
        << ": planned " << List(quotas[q].at("planned").get<std::vector<int64_t>>()) << " achieved "
        << List(achieved);
    if (outside) out << " (" << outside << " outside every bin)";
    out << "\n";
  }
  return out.str();
}

}  // namespace lsds::gen
