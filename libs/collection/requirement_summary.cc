#include "libs/collection/requirement_summary.h"

#include <algorithm>

namespace lsds {

size_t QuotaBinOf(const nlohmann::json& quota, double value) {
  const size_t n = quota.at("weights").size();
  if (quota.contains("class_ids")) {
    const std::vector<double> ids = quota.at("class_ids").get<std::vector<double>>();
    for (size_t b = 0; b < ids.size(); ++b)
      if (ids[b] == value) return b;
    return n;
  }
  const std::vector<double> edges = quota.at("bins").get<std::vector<double>>();
  for (size_t b = 0; b + 1 < edges.size(); ++b)
    if (value >= edges[b] &&
        (value < edges[b + 1] || (b + 2 == edges.size() && value <= edges[b + 1])))
      return b;
  return n;
}

std::string QuotaBinsText(const nlohmann::json& quota) {
  return quota.contains("classes") ? "classes " + quota.at("classes").dump()
                                   : "bins " + quota.at("bins").dump();
}

namespace {

// A rig's frame: gathered per step (FoldSteps counts the step).
void AddStepFrame(const nlohmann::json& quotas, const nlohmann::json& r, RequirementSummary* s) {
  RequirementSummary::Step& step = s->steps[r.at("step").get<int64_t>()];
  step.attempts = r.value("attempts", 1);
  step.estimate_met = r.value("step_met", false);
  ++step.cameras;
  step.cameras_met += r.value("achieved_met", false);
  step.bins.resize(quotas.size());
  for (size_t q = 0; q < quotas.size(); ++q)
    for (const nlohmann::json& check : r.at("checks")) {
      if (check.at("name").get<std::string>() != quotas[q].at("name").get<std::string>()) continue;
      const size_t none = quotas[q].at("weights").size();
      step.bins[q].push_back({QuotaBinOf(quotas[q], check.at("min").get<double>()),
                              check.contains("achieved")
                                  ? QuotaBinOf(quotas[q], check.at("achieved").get<double>())
                                  : none});
      break;
    }
}

}  // namespace

void AddRequirementSummary(const nlohmann::json& asked,
                           const Frame& truth,
                           RequirementSummary* summary) {
  if (asked.is_null()) return;
  const nlohmann::json& quotas = asked.at("quotas");
  if (summary->achieved.empty())
    for (const nlohmann::json& q : quotas)
      summary->achieved.push_back(
          {q.at("name").get<std::string>(), std::vector<int64_t>(q.at("weights").size() + 1, 0)});
  if (truth.requirements.is_null()) return;
  const nlohmann::json& r = truth.requirements;
  if (r.contains("step")) return AddStepFrame(quotas, r, summary);
  ++summary->frames;
  summary->attempts += r.value("attempts", 1);
  if (r.value("met", false)) ++summary->estimate_met;
  if (r.value("achieved_met", false))
    ++summary->achieved_met;
  else
    summary->missed.push_back(truth.index);
  // A quota's achieved bin: where the achieved value of the frame's check falls (the last slot
  // counts values outside every bin, or not measured).
  for (size_t q = 0; q < quotas.size(); ++q) {
    const std::string name = quotas[q].at("name").get<std::string>();
    for (const nlohmann::json& check : r.at("checks")) {
      if (check.at("name").get<std::string>() != name) continue;
      size_t bin = quotas[q].at("weights").size();  // "no bin"
      if (check.contains("achieved"))
        bin = QuotaBinOf(quotas[q], check.at("achieved").get<double>());
      ++summary->achieved[q].second[bin];
      break;  // one check per quota and frame
    }
  }
}

RequirementSummary FoldSteps(const nlohmann::json& asked, const RequirementSummary& in) {
  RequirementSummary out = in;
  out.steps.clear();
  const bool any = asked.value("cameras", "all") == "any";
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

void MergeRequirementSummary(const RequirementSummary& other, RequirementSummary* into) {
  into->frames += other.frames;
  into->attempts += other.attempts;
  into->estimate_met += other.estimate_met;
  into->achieved_met += other.achieved_met;
  into->missed.insert(into->missed.end(), other.missed.begin(), other.missed.end());
  std::sort(into->missed.begin(), into->missed.end());
  if (into->achieved.empty())
    into->achieved = other.achieved;
  else
    for (size_t q = 0; q < into->achieved.size() && q < other.achieved.size(); ++q)
      for (size_t b = 0; b < into->achieved[q].second.size(); ++b)
        into->achieved[q].second[b] += other.achieved[q].second.at(b);
  // A step's cameras may be in different shards: their frames join.
  for (const auto& [index, step] : other.steps) {
    RequirementSummary::Step& mine = into->steps[index];
    mine.attempts = step.attempts;
    mine.estimate_met = mine.estimate_met || step.estimate_met;
    mine.cameras += step.cameras;
    mine.cameras_met += step.cameras_met;
    mine.bins.resize(std::max(mine.bins.size(), step.bins.size()));
    for (size_t q = 0; q < step.bins.size(); ++q)
      mine.bins[q].insert(mine.bins[q].end(), step.bins[q].begin(), step.bins[q].end());
  }
}

nlohmann::json RequirementSummaryToJson(const RequirementSummary& s) {
  nlohmann::json achieved = nlohmann::json::array(), steps = nlohmann::json::array();
  for (const auto& [name, counts] : s.achieved)
    achieved.push_back({{"name", name}, {"counts", counts}});
  for (const auto& [index, step] : s.steps)
    steps.push_back({{"step", index},
                     {"attempts", step.attempts},
                     {"estimate_met", step.estimate_met},
                     {"cameras", step.cameras},
                     {"cameras_met", step.cameras_met},
                     {"bins", step.bins}});
  return {{"frames", s.frames},
          {"attempts", s.attempts},
          {"estimate_met", s.estimate_met},
          {"achieved_met", s.achieved_met},
          {"missed", s.missed},
          {"achieved", achieved},
          {"steps", steps}};
}

RequirementSummary RequirementSummaryFromJson(const nlohmann::json& j) {
  RequirementSummary s;
  s.frames = j.at("frames").get<int64_t>();
  s.attempts = j.at("attempts").get<int64_t>();
  s.estimate_met = j.at("estimate_met").get<int64_t>();
  s.achieved_met = j.at("achieved_met").get<int64_t>();
  s.missed = j.at("missed").get<std::vector<int64_t>>();
  for (const nlohmann::json& a : j.at("achieved"))
    s.achieved.push_back(
        {a.at("name").get<std::string>(), a.at("counts").get<std::vector<int64_t>>()});
  for (const nlohmann::json& step : j.at("steps")) {
    RequirementSummary::Step& t = s.steps[step.at("step").get<int64_t>()];
    t.attempts = step.at("attempts").get<int64_t>();
    t.estimate_met = step.at("estimate_met").get<bool>();
    t.cameras = step.at("cameras").get<int>();
    t.cameras_met = step.at("cameras_met").get<int>();
    t.bins = step.at("bins").get<std::vector<std::vector<std::pair<size_t, size_t>>>>();
  }
  return s;
}

}  // namespace lsds
