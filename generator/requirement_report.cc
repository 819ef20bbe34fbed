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

std::string Unit(const Plan& plan) {
  return plan.requirements.value("unit", "frame") == "step" ? "steps" : "frames";
}

}  // namespace

void AddRequirementSummary(const Plan& plan, const Frame& truth, RequirementSummary* summary) {
  lsds::AddRequirementSummary(plan.requirements, truth, summary);
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
  summary = FoldSteps(plan.requirements, summary);
  std::ostringstream out;
  out << "requirements: " << summary.frames << " " << Unit(plan) << " with a demand, "
      << summary.estimate_met << " met by estimate in " << summary.attempts << " draws";
  if (!summary.missed.empty())
    out << "; budget ran out on " << Unit(plan) << " " << List(summary.missed);
  out << "\n";
  const nlohmann::json& quotas = plan.requirements.at("quotas");
  for (size_t q = 0; q < quotas.size() && q < summary.achieved.size(); ++q) {
    std::vector<int64_t> estimated = summary.achieved[q].second;
    estimated.pop_back();
    out << "quota " << summary.achieved[q].first << " "
        << quotas[q].at("quantity").get<std::string>() << " " << QuotaBinsText(quotas[q])
        << ": planned " << List(quotas[q].at("planned").get<std::vector<int64_t>>())
        << " estimated " << List(estimated) << "\n";
  }
  return out.str();
}

std::string FormatRequirementSummary(const Plan& plan, const RequirementSummary& gathered) {
  if (plan.requirements.is_null()) return "";
  const RequirementSummary summary = FoldSteps(plan.requirements, gathered);
  std::ostringstream out;
  out << "requirements: " << summary.frames << " " << Unit(plan) << " with a demand, "
      << summary.estimate_met << " met by estimate, " << summary.achieved_met
      << " met in the rendered truth, "
      << FormatNumber(summary.frames ? static_cast<double>(summary.frames) / summary.attempts : 1.0)
      << " draws accepted per draw estimated";
  if (!summary.missed.empty()) out << "; missed " << Unit(plan) << " " << List(summary.missed);
  out << "\n";
  const nlohmann::json& quotas = plan.requirements.at("quotas");
  for (size_t q = 0; q < quotas.size() && q < summary.achieved.size(); ++q) {
    std::vector<int64_t> achieved = summary.achieved[q].second;
    const int64_t outside = achieved.back();
    achieved.pop_back();
    out << "quota " << summary.achieved[q].first << " "
        << quotas[q].at("quantity").get<std::string>() << " " << QuotaBinsText(quotas[q])
        << ": planned " << List(quotas[q].at("planned").get<std::vector<int64_t>>()) << " achieved "
        << List(achieved);
    if (outside) out << " (" << outside << " outside every bin)";
    out << "\n";
  }
  return out.str();
}

}  // namespace lsds::gen
