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

// The bin of quota `q` (provenance form) a value falls in; the number of bins
// when it falls in none. A class quota's bins are its class ids.
size_t BinOf(const nlohmann::json& q, double v) {
  const size_t n = q.at("weights").size();
  if (q.contains("class_ids")) {
    const std::vector<double> ids = q.at("class_ids").get<std::vector<double>>();
    for (size_t b = 0; b < ids.size(); ++b)
      if (ids[b] == v) return b;
    return n;
  }
  const std::vector<double> edges = q.at("bins").get<std::vector<double>>();
  for (size_t b = 0; b + 1 < edges.size(); ++b)
    if (v >= edges[b] && (v < edges[b + 1] || (b + 2 == edges.size() && v <= edges[b + 1])))
      return b;
  return n;
}

// "bins [0,10,20]" or "classes ["car","truck"]".
std::string BinsText(const nlohmann::json& q) {
  return q.contains("classes") ? "classes " + q.at("classes").dump()
                               : "bins " + q.at("bins").dump();
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
  if (r.contains("step")) {
    // A rig's frame: gathered per step (FoldSteps counts the step).
    RequirementSummary::Step& step = summary->steps[r.at("step").get<int64_t>()];
    step.attempts = r.value("attempts", 1);
    step.estimate_met = r.value("step_met", false);
    ++step.cameras;
    step.cameras_met += r.value("achieved_met", false);
    step.bins.resize(quotas.size());
    for (size_t q = 0; q < quotas.size(); ++q)
      for (const nlohmann::json& check : r.at("checks")) {
        if (check.at("name").get<std::string>() != quotas[q].at("name").get<std::string>())
          continue;
        const size_t none = quotas[q].at("weights").size();
        step.bins[q].push_back({BinOf(quotas[q], check.at("min").get<double>()),
                                check.contains("achieved")
                                    ? BinOf(quotas[q], check.at("achieved").get<double>())
                                    : none});
        break;
      }
    return;
  }
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
    for (const nlohmann::json& check : r.at("checks")) {
      if (check.at("name").get<std::string>() != name) continue;
      size_t bin = quotas[q].at("weights").size();  // "no bin"
      if (check.contains("achieved")) bin = BinOf(quotas[q], check.at("achieved").get<double>());
      ++summary->achieved[q].second[bin];
      break;  // one check per quota and frame
    }
  }
}

namespace {

// A rig capture's steps counted as the units of the summary: a step meets its
// demand when every camera's truth does (cameras:all) or one does (any); it
// counts in a quota's demanded bin when those cameras are in it, else in the
// first camera's bin.
RequirementSummary FoldSteps(const Plan& plan, const RequirementSummary& in) {
  RequirementSummary out = in;
  const bool any = plan.requirements.value("cameras", "all") == "any";
  for (const auto& [index, step] : in.steps) {
    ++out.frames;
    out.attempts += step.attempts;
    out.estimate_met += step.estimate_met;
    const bool met = any ? step.cameras_met > 0 : step.cameras_met == step.cameras;
    if (met)
      ++out.achieved_met;
    else
      out.missed.push_back(index);
    for (size_t q = 0; q < step.bins.size() && q < out.achieved.size(); ++q) {
      if (step.bins[q].empty()) continue;
      const size_t demanded = step.bins[q].front().first;
      size_t hits = 0;
      for (const auto& [d, a] : step.bins[q]) hits += a == demanded;
      const bool in_bin = any ? hits > 0 : hits == step.bins[q].size();
      ++out.achieved[q].second[in_bin ? demanded : step.bins[q].front().second];
    }
  }
  return out;
}

std::string Unit(const Plan& plan) {
  return plan.requirements.value("unit", "frame") == "step" ? "steps" : "frames";
}

}  // namespace

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
  summary = FoldSteps(plan, summary);
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
        << quotas[q].at("quantity").get<std::string>() << " " << BinsText(quotas[q]) << ": planned "
        << List(quotas[q].at("planned").get<std::vector<int64_t>>()) << " estimated "
        << List(estimated) << "\n";
  }
  return out.str();
}

std::string FormatRequirementSummary(const Plan& plan, const RequirementSummary& gathered) {
  if (plan.requirements.is_null()) return "";
  const RequirementSummary summary = FoldSteps(plan, gathered);
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
        << quotas[q].at("quantity").get<std::string>() << " " << BinsText(quotas[q]) << ": planned "
        << List(quotas[q].at("planned").get<std::vector<int64_t>>()) << " achieved "
        << List(achieved);
    if (outside) out << " (" << outside << " outside every bin)";
    out << "\n";
  }
  return out.str();
}

}  // namespace lsds::gen
