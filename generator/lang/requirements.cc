#include "generator/lang/requirements.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "generator/lang/random.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/oriented_box.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

const std::vector<std::string> kTargetQuantities = {
    "visibility", "occlusion", "in_frame", "size_px", "gsd", "distance", "view_angle"};
const std::vector<std::string> kFrameQuantities = {"altitude", "off_nadir"};

std::string QuantityOf(const Node& where, const std::string& key) {
  const std::string canonical = CanonicalKey(key);
  for (const std::string& q : RequirementQuantities())
    if (CanonicalKey(q) == canonical) return q;
  where.Fail("unknown quantity '" + key + "'" + DidYouMean(canonical, RequirementQuantities()));
}

Bound ReadBound(const Node& n, const std::string& quantity) {
  Bound b;
  b.quantity = quantity;
  if (!n->is_array() || n->size() != 2 || !IsNumber(n->at(0)) || !IsNumber(n->at(1)))
    n.Fail("a bound is [min, max]");
  b.lo = ReadNumber(n.Item(0));
  b.hi = ReadNumber(n.Item(1));
  if (b.lo > b.hi) n.Fail("a bound [min, max] needs min <= max");
  return b;
}

std::string ReadTarget(const Definition& d, const Program& scene) {
  const Node t = d.body.Find("target");
  if (!t) return "";
  const std::string name = ReadString(t);
  const Definition* o = scene.Find(name);
  if (!o || o->kind != "object") {
    std::vector<std::string> names;
    for (const Definition& s : scene.definitions)
      if (s.kind == "object") names.push_back(s.symbol);
    t.Fail("'" + name + "' is not an object of the scene" + DidYouMean(name, names));
  }
  return name;
}

const std::vector<std::string> kRequireKeys = {"target",
                                               "visibility",
                                               "occlusion",
                                               "in_frame",
                                               "size_px",
                                               "gsd",
                                               "distance",
                                               "view_angle",
                                               "altitude",
                                               "off_nadir",
                                               "probability",
                                               "p",
                                               "budget",
                                               "on_budget"};
const std::vector<std::string> kQuotaKeys = {
    "target", "quantity", "bins", "weights", "tolerance", "budget", "on_budget"};

void ReadBudget(const Definition& d, RequirementSet* set) {
  if (const Node b = d.body.Find("budget")) {
    const double v = ReadNumber(b);
    if (v < 0 || v > 100000 || v != std::floor(v))
      b.Fail("budget is a whole number in [0, 100000]");
    set->budget = std::max(set->budget, static_cast<int>(v));
  }
  if (const Node o = d.body.Find("onbudget")) {
    const std::string v = ReadString(o);
    if (v != "keep" && v != "fail") o.Fail("on_budget is keep (the default) or fail");
    if (v == "fail") set->fail_on_budget = true;
  }
}

}  // namespace

const std::vector<std::string>& RequirementQuantities() {
  static const std::vector<std::string> all = [] {
    std::vector<std::string> v = kTargetQuantities;
    v.insert(v.end(), kFrameQuantities.begin(), kFrameQuantities.end());
    return v;
  }();
  return all;
}

bool IsFrameQuantity(const std::string& quantity) {
  return std::find(kFrameQuantities.begin(), kFrameQuantities.end(), quantity) !=
         kFrameQuantities.end();
}

bool IsRequirementKind(const std::string& kind) { return kind == "require" || kind == "quota"; }

void CheckRequirementDefinition(const Definition& d) {
  d.body.CheckKeys(d.kind == "require" ? kRequireKeys : kQuotaKeys, d.kind + " " + d.symbol);
}

std::map<std::string, double> GeometricMeasures(const OrientedBox& box,
                                                const PinholeCamera& camera,
                                                const Rigid3d& cam_from_world) {
  std::map<std::string, double> m;
  const Eigen::Vector3d centre = CameraCenterInWorld(cam_from_world);
  const Eigen::Vector3d to_camera = centre - box.center;
  m["distance"] = to_camera.norm();
  m["view_angle"] =
      std::acos(std::clamp(to_camera.z() / std::max(1e-12, to_camera.norm()), -1.0, 1.0)) *
      kRadToDeg;
  m["gsd"] = m["distance"] / camera.fx;
  m["in_frame"] = InFrameFraction(box, camera, cam_from_world);
  double size = 0;
  if (const auto b = ProjectedBounds(box, camera, cam_from_world)) {
    const double w = std::min<double>(b->x1, camera.width) - std::max(0.0, b->x0);
    const double h = std::min<double>(b->y1, camera.height) - std::max(0.0, b->y0);
    size = std::max(0.0, std::max(w, h));
  }
  m["size_px"] = size;
  return m;
}

std::map<std::string, double> FrameMeasures(const Plan& plan, const Rigid3d& cam_from_world) {
  const Eigen::Vector3d c = CameraCenterInWorld(cam_from_world);
  const double ground = plan.terrain.present ? TerrainHeight(plan.terrain, c.x(), c.y()) : 0.0;
  // The optical axis (camera +z) in the world.
  const Eigen::Vector3d axis = cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
  return {{"altitude", c.z() - ground},
          {"off_nadir", std::acos(std::clamp(-axis.z(), -1.0, 1.0)) * kRadToDeg}};
}

FrameMeasure MeasureTruth(const Plan& plan,
                          const PlannedFrame& frame,
                          const std::vector<ObjectTruth>& objects) {
  FrameMeasure m;
  m.frame = FrameMeasures(plan, frame.cam_from_world);
  for (const ObjectTruth& o : objects) {
    TargetMeasure t;
    t.object = o.name;
    t.values = GeometricMeasures(o.obb, frame.camera, frame.cam_from_world);
    t.values["in_frame"] = o.in_frame;
    t.values["visibility"] = o.visibility;
    t.values["occlusion"] = 1.0 - o.visibility;
    m.targets.push_back(std::move(t));
  }
  return m;
}

RequirementSet ReadRequirements(const Program& capture, const Program& scene) {
  RequirementSet set;
  bool budget_given = false;
  for (const Definition& d : capture.definitions) {
    if (!IsRequirementKind(d.kind)) continue;
    CheckRequirementDefinition(d);
    if (d.body.Find("budget")) {
      if (!budget_given) set.budget = 0;
      budget_given = true;
    }
    ReadBudget(d, &set);
    const std::string target = ReadTarget(d, scene);
    if (d.kind == "require") {
      Requirement r;
      r.name = d.symbol;
      r.target = target;
      for (const auto& [key, node] : d.body.Members()) {
        const std::string k = CanonicalKey(key);
        if (k == "target" || k == "budget" || k == "onbudget") continue;
        if (k == "probability" || k == "p") {
          r.probability = ReadNumber(node);
          if (!(r.probability >= 0 && r.probability <= 1)) node.Fail("a probability is in [0, 1]");
          continue;
        }
        const std::string q = QuantityOf(node, key);
        if (!IsFrameQuantity(q) && target.empty())
          node.FailKey("'" + q + "' is a quantity of a target: add target:OBJECT");
        r.bounds.push_back(ReadBound(node, q));
      }
      if (r.bounds.empty()) d.body.Fail("require " + d.symbol + " bounds nothing");
      set.requirements.push_back(r);
    } else {
      Quota q;
      q.name = d.symbol;
      q.target = target;
      const Node quantity = d.body.Find("quantity");
      if (!quantity)
        d.body.Fail("a quota needs quantity:NAME (" + Join(RequirementQuantities(), ", ") + ")");
      q.quantity = QuantityOf(quantity, ReadString(quantity));
      if (!IsFrameQuantity(q.quantity) && target.empty())
        quantity.Fail("'" + q.quantity + "' is a quantity of a target: add target:OBJECT");
      const Node bins = d.body.Find("bins");
      if (!bins || !bins->is_array() || bins->size() < 2)
        (bins ? bins : d.body)
            .Fail("a quota needs bins:[e0, e1, ..., en] (n bins, edges ascending)");
      for (size_t i = 0; i < bins->size(); ++i) {
        q.edges.push_back(ReadNumber(bins.Item(i)));
        if (i > 0 && q.edges[i] <= q.edges[i - 1]) bins.Item(i).Fail("bin edges must ascend");
      }
      const size_t n = q.edges.size() - 1;
      q.weights.assign(n, 1.0);
      if (const Node w = d.body.Find("weights")) {
        if (!w->is_array() || w->size() != n)
          w.Fail("weights:[...] needs one weight per bin (" + std::to_string(n) + ")");
        for (size_t i = 0; i < n; ++i) {
          q.weights[i] = ReadNumber(w.Item(i));
          if (q.weights[i] < 0) w.Item(i).Fail("a weight is >= 0");
        }
      }
      const double sum = std::accumulate(q.weights.begin(), q.weights.end(), 0.0);
      if (sum <= 0) d.body.Fail("the quota's weights sum to 0");
      for (double& w : q.weights) w /= sum;
      if (const Node t = d.body.Find("tolerance")) {
        q.tolerance = ReadNumber(t);
        if (!(q.tolerance >= 0 && q.tolerance <= 1)) t.Fail("tolerance is a share in [0, 1]");
      }
      set.quotas.push_back(q);
    }
  }
  return set;
}

DemandPlanner::DemandPlanner(const RequirementSet& set, uint64_t seed, int64_t total_frames)
    : set_(set), seed_(seed) {
  // Stratified: each bin gets its share of the frames (largest remainder),
  // and a shuffle seeded by (seed, quota) spreads the bins over the frames. It
  // depends on the seed and the frame count only, never on which frames are
  // planned.
  for (size_t q = 0; q < set.quotas.size(); ++q) {
    const Quota& quota = set.quotas[q];
    const size_t n = quota.weights.size();
    std::vector<int64_t> counts(n);
    std::vector<std::pair<double, size_t>> remainders;
    int64_t given = 0;
    for (size_t b = 0; b < n; ++b) {
      const double exact = quota.weights[b] * static_cast<double>(total_frames);
      counts[b] = static_cast<int64_t>(std::floor(exact));
      given += counts[b];
      remainders.push_back({exact - std::floor(exact), b});
    }
    std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) {
      return a.first > b.first;
    });
    for (size_t i = 0; given < total_frames && i < remainders.size(); ++i, ++given)
      ++counts[remainders[i].second];
    std::vector<int> bins;
    for (size_t b = 0; b < n; ++b) bins.insert(bins.end(), counts[b], static_cast<int>(b));
    Rng rng = Rng::For(seed, StreamTag::kQuota, q);
    for (size_t i = bins.size(); i > 1; --i)
      std::swap(bins[i - 1],
                bins[static_cast<size_t>(rng.UniformInt(0, static_cast<int64_t>(i) - 1))]);
    bin_of_frame_.push_back(std::move(bins));
  }
}

FrameDemand DemandPlanner::For(int64_t k) const {
  FrameDemand d;
  for (size_t i = 0; i < set_.requirements.size(); ++i) {
    const Requirement& r = set_.requirements[i];
    // Scenic's require[p]: the requirement holds on a frame with probability
    // p, drawn from the frame's own stream.
    if (r.probability >= 1 ||
        Rng::For(seed_, StreamTag::kRequire, static_cast<uint64_t>(k), i).Uniform() < r.probability)
      d.active.push_back(&r);
  }
  for (size_t q = 0; q < set_.quotas.size(); ++q)
    if (k >= 0 && k < static_cast<int64_t>(bin_of_frame_[q].size()))
      d.bins.push_back({&set_.quotas[q], bin_of_frame_[q][static_cast<size_t>(k)]});
  return d;
}

std::vector<int64_t> DemandPlanner::PlannedCounts(size_t q) const {
  std::vector<int64_t> counts(set_.quotas[q].weights.size(), 0);
  for (int b : bin_of_frame_[q]) ++counts[static_cast<size_t>(b)];
  return counts;
}

int QuotaBin(const Quota& quota, double value) {
  const size_t n = quota.edges.size() - 1;
  for (size_t b = 0; b < n; ++b)
    if (value >= quota.edges[b] &&
        (value < quota.edges[b + 1] || (b + 1 == n && value <= quota.edges[n])))
      return static_cast<int>(b);
  return -1;
}

namespace {

// One demanded (object, quantity, [lo, hi]) of a frame.
struct Check {
  std::string name;    // requirement or quota symbol
  std::string target;  // object symbol, empty for frame quantities
  std::string quantity;
  double lo, hi;
  bool half_open;  // a quota bin other than the last: [lo, hi)
};

std::vector<Check> ChecksOf(const FrameDemand& demand) {
  std::vector<Check> checks;
  for (const Requirement* r : demand.active)
    for (const Bound& b : r->bounds)
      checks.push_back(
          {r->name, IsFrameQuantity(b.quantity) ? "" : r->target, b.quantity, b.lo, b.hi, false});
  for (const auto& [q, bin] : demand.bins)
    checks.push_back({q->name,
                      IsFrameQuantity(q->quantity) ? "" : q->target,
                      q->quantity,
                      q->edges[bin],
                      q->edges[bin + 1],
                      bin + 2 < static_cast<int>(q->edges.size())});
  return checks;
}

double Outside(const Check& c, double v) {
  if (v < c.lo) return c.lo - v;
  if (v > c.hi || (c.half_open && v >= c.hi)) return std::max(v - c.hi, 1e-9);
  return 0;
}

// The copies of `symbol` in the measure ("O1#1", "O1#2", ...).
std::vector<const TargetMeasure*> CopiesOf(const FrameMeasure& m, const std::string& symbol) {
  std::vector<const TargetMeasure*> copies;
  for (const TargetMeasure& t : m.targets)
    if (t.object.substr(0, t.object.rfind('#')) == symbol) copies.push_back(&t);
  return copies;
}

// Scale of each quantity so that violations of different units add up.
double Scale(double lo, double hi) { return std::max({1e-6, hi - lo, std::abs(hi) * 0.1}); }

}  // namespace

double Violation(const FrameDemand& demand, const FrameMeasure& measure) {
  double total = 0;
  for (const Check& c : ChecksOf(demand)) {
    const double scale = Scale(c.lo, c.hi);
    if (c.target.empty()) {
      total += Outside(c, measure.frame.at(c.quantity)) / scale;
      continue;
    }
    const auto copies = CopiesOf(measure, c.target);
    if (copies.empty()) total += 1;  // out of view: every bound fails
    for (const TargetMeasure* t : copies) total += Outside(c, t->values.at(c.quantity)) / scale;
  }
  return total;
}

nlohmann::json DemandRecord(const FrameDemand& demand, const FrameMeasure& measure) {
  nlohmann::json checks = nlohmann::json::array();
  bool met = true;
  for (const Check& c : ChecksOf(demand)) {
    auto add = [&](const std::string& object, std::optional<double> v) {
      nlohmann::json j = {{"name", c.name}, {"quantity", c.quantity}};
      if (!object.empty()) j["object"] = object;
      j["min"] = c.lo;
      j["max"] = c.hi;
      const bool ok = v && Outside(c, *v) == 0;
      if (c.half_open) j["max_exclusive"] = true;
      if (v) j["estimate"] = *v;
      j["met"] = ok;
      met = met && ok;
      checks.push_back(j);
    };
    if (c.target.empty()) {
      add("", measure.frame.at(c.quantity));
      continue;
    }
    const auto copies = CopiesOf(measure, c.target);
    if (copies.empty()) add(c.target, std::nullopt);
    for (const TargetMeasure* t : copies) add(t->object, t->values.at(c.quantity));
  }
  return {{"met", met}, {"checks", checks}};
}

nlohmann::json AchievedRecord(const nlohmann::json& planned, const FrameMeasure& achieved) {
  nlohmann::json record = planned;
  bool met = true;
  for (nlohmann::json& check : record["checks"]) {
    const std::string quantity = check.at("quantity").get<std::string>();
    std::optional<double> v;
    if (!check.contains("object")) {
      if (const auto it = achieved.frame.find(quantity); it != achieved.frame.end()) v = it->second;
    } else {
      for (const TargetMeasure& t : achieved.targets)
        if (t.object == check.at("object").get<std::string>()) v = t.values.at(quantity);
    }
    Check c{"",
            "",
            quantity,
            check.at("min").get<double>(),
            check.at("max").get<double>(),
            check.value("max_exclusive", false)};
    const bool ok = v && Outside(c, *v) == 0;
    if (v) check["achieved"] = *v;
    check["achieved_met"] = ok;
    met = met && ok;
  }
  record["achieved_met"] = met;
  return record;
}

nlohmann::json RequirementsProvenance(const RequirementSet& set, const DemandPlanner& planner) {
  nlohmann::json requirements = nlohmann::json::array();
  for (const Requirement& r : set.requirements) {
    nlohmann::json bounds = nlohmann::json::object();
    for (const Bound& b : r.bounds) bounds[b.quantity] = {b.lo, b.hi};
    nlohmann::json j = {{"name", r.name}};
    if (!r.target.empty()) j["target"] = r.target;
    j["bounds"] = bounds;
    j["probability"] = r.probability;
    requirements.push_back(j);
  }
  nlohmann::json quotas = nlohmann::json::array();
  for (size_t q = 0; q < set.quotas.size(); ++q) {
    const Quota& quota = set.quotas[q];
    nlohmann::json j = {{"name", quota.name}};
    if (!quota.target.empty()) j["target"] = quota.target;
    j["quantity"] = quota.quantity;
    j["bins"] = quota.edges;
    j["weights"] = quota.weights;
    j["tolerance"] = quota.tolerance;
    j["planned"] = planner.PlannedCounts(q);
    quotas.push_back(j);
  }
  return {{"requirements", requirements},
          {"quotas", quotas},
          {"budget", set.budget},
          {"on_budget", set.fail_on_budget ? "fail" : "keep"}};
}

}  // namespace lsds
