#include "evaluate/suggest.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <set>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::evaluate {

namespace {

constexpr double kLeastWeight = 0.05;  // a stratum the model handles keeps a few frames
constexpr double kMinSpread = 0.1;     // recall spread below which a condition asks for nothing
constexpr size_t kMaxQuotas = 2;       // each quota is one more demand on every frame
constexpr double kOpenEdge = 1e5;      // LCAP bins are finite: [256, inf) becomes [256, 1e5]

// The LCAP quota quantity of a condition (docs/languages.md, "Requirements
// and quotas"), and whether it is a quantity of a target.
struct Quantity {
  const char* condition;
  const char* quantity;
  bool of_target;
};

const Quantity kQuantities[] = {{"size_px", "size_px", true},
                                {"visibility", "visibility", true},
                                {"distance_m", "distance", true},
                                {"class", "class", true},
                                {"altitude_agl_m", "altitude", false},
                                {"off_nadir_deg", "off_nadir", false},
                                {"sun_elevation_deg", "sun_elevation", false}};

// One quota to add: its weights per bin of the condition, trimmed to the bins
// from the first to the last with a weight.
struct Proposal {
  const Quantity* quantity = nullptr;
  const ConditionBins* bins = nullptr;
  std::vector<double> weights;  // per bin; 0: outside the range the collection reaches
  double spread = 0;            // best minus worst recall@.5
  std::string why;              // the worst stratum, for the comment
};

// The LSCENE symbol most of the collection's objects are copies of ("T" of
// "T#2"); empty when the truth names none.
std::string MainTarget(const EvaluationTruth& truth) {
  std::map<std::string, int64_t> counts;
  truth.ForEachImage([&](TruthImage&& image) {
    for (const ObjectFacts& o : image.objects)
      if (!o.name.empty()) ++counts[o.name.substr(0, o.name.find('#'))];
  });
  std::string best;
  for (const auto& [symbol, n] : counts)
    if (best.empty() || n > counts[best]) best = symbol;
  return best;
}

// Weights: 1 - recall@.5 (at least kLeastWeight) for a stratum with objects,
// 1 for an empty cell between two that have objects, 0 outside them.
Proposal Propose(const Quantity& q, const ConditionBins& c, const ConditionMetrics& m) {
  Proposal p{&q, &c, std::vector<double>(c.bins.size(), 0.0), 0, ""};
  double best = 0, worst = 1;
  int first = -1, last = -1;
  for (const StratumMetrics& s : m.strata) {
    if (s.objects == 0) continue;
    const auto at = std::find(c.bins.begin(), c.bins.end(), s.label);
    if (at == c.bins.end()) continue;
    const int b = static_cast<int>(at - c.bins.begin());
    p.weights[b] = std::max(kLeastWeight, 1 - s.recall_50);
    first = first < 0 ? b : std::min(first, b);
    last = std::max(last, b);
    best = std::max(best, s.recall_50);
    worst = std::min(worst, s.recall_50);
  }
  for (int b = first + 1; b < last; ++b)
    if (p.weights[b] == 0) p.weights[b] = 1;  // an empty cell inside the reached range
  p.spread = first < 0 ? 0 : best - worst;
  if (!m.strata.empty() && m.strata.front().objects > 0) {
    const StratumMetrics& w = m.strata.front();
    p.why = c.name + " " + w.label + ": recall@.5 " + FormatNumber(w.recall_50, 3) + " of " +
            std::to_string(w.objects) + " objects";
  }
  return p;
}

std::string Symbol(const std::string& condition, const std::string& capture) {
  std::string base = "SUGGEST_";
  for (const char ch : condition) base += static_cast<char>(std::toupper(ch));
  std::string symbol = base;
  for (int n = 2; std::regex_search(capture, std::regex("\\b" + symbol + "\\s*=")); ++n)
    symbol = base + "_" + std::to_string(n);
  return symbol;
}

// quota{...} of a proposal, its bins cut to those with a weight.
std::string QuotaText(const Proposal& p, const std::string& target) {
  std::vector<int> kept;
  for (size_t b = 0; b < p.weights.size(); ++b)
    if (p.weights[b] > 0) kept.push_back(static_cast<int>(b));
  std::string text = "quota{";
  if (p.quantity->of_target) text += "target:" + target + ",";
  text += "quantity:" + std::string(p.quantity->quantity) + ",";
  std::vector<std::string> parts;
  if (p.bins->edges.empty()) {  // categorical: the class quota
    for (int b : kept) parts.push_back(p.bins->bins[b] + ":" + FormatNumber(p.weights[b], 3));
    return text + "classes:{" + Join(parts, ",") + "}}";
  }
  const auto edge = [](double e) { return FormatNumber(std::isinf(e) ? kOpenEdge : e, 6); };
  for (int b : kept) parts.push_back(edge(p.bins->edges[b]));
  parts.push_back(edge(p.bins->edges[kept.back() + 1]));
  text += "bins:[" + Join(parts, ",") + "],weights:[";
  parts.clear();
  for (int b : kept) parts.push_back(FormatNumber(p.weights[b], 3));
  return text + Join(parts, ",") + "]}";
}

// A quota of the capture whose weights the suggestion raises where the model
// did worst: each bin's weight times 1 - recall@.5 (at least kLeastWeight);
// a bin without objects keeps its weight.
struct Reweighting {
  const nlohmann::json* quota = nullptr;  // provenance form
  std::vector<double> weights;
  double spread = 0;
  std::string why;
};

Reweighting Reweigh(const nlohmann::json& quota,
                    const ConditionBins& c,
                    const ConditionMetrics& m) {
  Reweighting r{&quota, quota.at("weights").get<std::vector<double>>(), 0, ""};
  double best = 0, worst = 1;
  bool any = false;
  for (const StratumMetrics& s : m.strata) {
    const auto at = std::find(c.bins.begin(), c.bins.end(), s.label);
    if (s.objects == 0 || at == c.bins.end()) continue;
    r.weights[at - c.bins.begin()] *= std::max(kLeastWeight, 1 - s.recall_50);
    best = std::max(best, s.recall_50);
    worst = std::min(worst, s.recall_50);
    any = true;
  }
  r.spread = any ? best - worst : 0;
  double total = 0;
  for (double w : r.weights) total += w;
  for (double& w : r.weights) w = total > 0 ? w / total : w;
  if (!m.strata.empty() && m.strata.front().objects > 0) {
    const StratumMetrics& w = m.strata.front();
    r.why = c.name + " " + w.label + ": recall@.5 " + FormatNumber(w.recall_50, 3) + " of " +
            std::to_string(w.objects) + " objects";
  }
  return r;
}

// The capture with the weights of quota definition `r` replaced (a class
// quota's `classes:{...}` written again with its names), and a comment line
// before the definition saying why.
std::string Reweight(const std::string& capture, const Reweighting& r) {
  const std::string name = r.quota->at("name").get<std::string>();
  std::smatch match;
  const std::regex start("(^|\\n)([ \\t]*)" + name + R"([ \t]*=[ \t]*quota[ \t]*\{)");
  if (!std::regex_search(capture, match, start))
    throw Error("the collection's capture has no definition '" + name +
                " = quota{...}' for its quota " + name + " (provenance.capture_source)");
  const size_t line = static_cast<size_t>(match.position(0)) + match.length(1);
  const size_t open = static_cast<size_t>(match.position(0) + match.length(0)) - 1;
  size_t close = open;
  for (int depth = 0; close < capture.size(); ++close) {
    depth += capture[close] == '{' ? 1 : capture[close] == '}' ? -1 : 0;
    if (depth == 0) break;
  }
  std::string body = capture.substr(open + 1, close - open - 1);
  std::vector<std::string> parts;
  // A class quota's shares are `classes:{name:share,...}`, or (`classes:[...]`)
  // its `weights`, as a numeric quota's.
  const std::regex class_shares(R"(classes\s*:\s*\{[^}]*\})");
  if (r.quota->contains("classes") && std::regex_search(body, class_shares)) {
    const auto names = r.quota->at("classes").get<std::vector<std::string>>();
    for (size_t b = 0; b < names.size(); ++b)
      parts.push_back(names[b] + ":" + FormatNumber(r.weights[b], 3));
    body = std::regex_replace(body, class_shares, "classes:{" + Join(parts, ",") + "}");
  } else {
    for (double w : r.weights) parts.push_back(FormatNumber(w, 3));
    const std::string weights = "weights:[" + Join(parts, ",") + "]";
    const std::regex old(R"(weights\s*:\s*\[[^\]]*\])");
    if (std::regex_search(body, old)) {
      body = std::regex_replace(body, old, weights);
    } else {
      body.erase(body.find_last_not_of(" \t\r\n") + 1);
      body += "," + weights;
    }
  }
  return capture.substr(0, line) + "# lsds evaluate --suggest: weights raised, worst " + r.why +
         "\n" + capture.substr(line, open + 1 - line) + body + capture.substr(close);
}

// The capture with ` ONE(SYMBOL)` appended to its start rule `LCAP = ...`.
std::string AddToStartRule(const std::string& capture, const std::vector<std::string>& symbols) {
  std::smatch match;
  const std::regex start(R"((^|\n)[ \t]*LCAP[ \t]*=[^\n#]*)");
  if (!std::regex_search(capture, match, start))
    throw Error("the collection's capture has no start rule 'LCAP = ...' to extend");
  std::string added;
  for (const std::string& s : symbols) added += " ONE(" + s + ")";
  const size_t end = static_cast<size_t>(match.position(0) + match.length(0));
  size_t cut = end;
  while (cut > 0 && (capture[cut - 1] == ' ' || capture[cut - 1] == '\t')) --cut;
  return capture.substr(0, cut) + added + capture.substr(cut);
}

}  // namespace

Suggestion SuggestCapture(const EvaluationTruth& truth,
                          const std::vector<ConditionBins>& conditions,
                          const EvaluationReport& report) {
  const std::string& capture = truth.capture_source;
  const size_t first = capture.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || capture[first] == '{') {
    throw Error(std::string("--suggest extends the collection's LCAP capture in text notation, ") +
                (first == std::string::npos ? "and the collection records none"
                                            : "and it records the JSON form") +
                " (provenance.capture_source)");
  }
  const std::string target = MainTarget(truth);
  // The capture's own quotas: reweighted where the model did worst; a
  // condition of the same quantity adds no parallel quota.
  std::vector<Reweighting> reweightings;
  std::set<std::string> quota_quantities;
  for (const ConditionBins& c : conditions) {
    if (c.quota < 0) continue;
    const nlohmann::json& quota = truth.quotas.at(c.quota);
    quota_quantities.insert(quota.at("quantity").get<std::string>());
    const auto m = std::find_if(report.strata.begin(),
                                report.strata.end(),
                                [&](const ConditionMetrics& s) { return s.name == c.name; });
    if (m == report.strata.end()) continue;
    Reweighting r = Reweigh(quota, c, *m);
    if (r.spread >= kMinSpread) reweightings.push_back(std::move(r));
  }
  std::vector<Proposal> proposals;
  for (const Quantity& q : kQuantities) {
    if (quota_quantities.count(q.quantity)) continue;
    const auto c = std::find_if(conditions.begin(), conditions.end(), [&](const ConditionBins& b) {
      return b.name == q.condition;
    });
    const auto m = std::find_if(report.strata.begin(),
                                report.strata.end(),
                                [&](const ConditionMetrics& s) { return s.name == q.condition; });
    if (c == conditions.end() || m == report.strata.end() || (q.of_target && target.empty()))
      continue;
    Proposal p = Propose(q, *c, *m);
    if (p.spread >= kMinSpread) proposals.push_back(std::move(p));
  }
  std::stable_sort(proposals.begin(), proposals.end(), [](const Proposal& a, const Proposal& b) {
    return a.spread > b.spread;
  });
  if (proposals.size() > kMaxQuotas) proposals.resize(kMaxQuotas);

  Suggestion out;
  std::string reweighted = capture;
  for (const Reweighting& r : reweightings) {
    reweighted = Reweight(reweighted, r);
    out.quotas.push_back(r.quota->at("name").get<std::string>());
  }
  std::string definitions;
  for (const Proposal& p : proposals) {
    const std::string symbol = Symbol(p.bins->name, capture + definitions);
    definitions += "# lsds evaluate --suggest: worst " + p.why + "\n" + symbol + " = " +
                   QuotaText(p, target) + "\n";
    out.quotas.push_back(symbol);
  }
  std::vector<std::string> added(out.quotas.begin() + reweightings.size(), out.quotas.end());
  std::string lcap = added.empty() ? reweighted : AddToStartRule(reweighted, added);
  if (!lcap.empty() && lcap.back() != '\n') lcap += '\n';
  if (out.quotas.empty())
    lcap += "# lsds evaluate --suggest: no condition's strata differ by 0.1 in recall@.5\n";
  out.lcap = lcap + definitions;
  return out;
}

}  // namespace lsds::evaluate
