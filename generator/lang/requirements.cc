#include "generator/lang/requirements.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "generator/lang/random.h"
#include "generator/lang/vocabulary.h"
#include "generator/plan/relations.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/oriented_box.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The quantities a requirement bounds, from the vocabulary's require table.
const std::vector<std::string>& TargetQuantities() {
  static const std::vector<std::string> q =
      KindVocabulary("require").KeysWithRole("target quantity");
  return q;
}
const std::vector<std::string>& FrameQuantities() {
  static const std::vector<std::string> q =
      KindVocabulary("require").KeysWithRole("frame quantity");
  return q;
}

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
  std::string name = ReadString(t);
  const Definition* o = scene.Find(name);
  if (!o || o->kind != "object") {
    std::vector<std::string> names;
    for (const Definition& s : scene.definitions)
      if (s.kind == "object") names.push_back(s.symbol);
    t.Fail("'" + name + "' is not an object of the scene" + DidYouMean(name, names));
  }
  return name;
}

// The relations relative to the camera a requirement may state, as bounds.
bool IsCameraRelation(const std::string& canonical) {
  return canonical == "facing" || canonical == "infrontof" || canonical == "behind" ||
         canonical == "near" || canonical == "visiblefrom";
}

// How far ahead (or behind, negative) a camera relation reaches by default.
constexpr double kCameraRelationReachM = 10000;

// `FACING:CAMERA` (`{CAMERA: deg}`), `IN FRONT OF:CAMERA` / `BEHIND:CAMERA`
// (`{CAMERA: m}`), `NEAR:{CAMERA: m}`, `VISIBLE FROM:CAMERA`: the bound each
// stands for (docs/languages.md, "Relations to the camera").
Bound CameraRelationBound(const Node& n, const std::string& canonical, const std::string& camera) {
  std::string ref;
  std::optional<double> amount;
  if (n->is_object() && n->size() == 1) {
    const auto [key, value] = n.Members().front();
    ref = key;
    amount = ReadNumber(value);
    if (!(*amount >= 0)) value.Fail("a relation's angle or distance is >= 0");
  } else {
    ref = ReadString(n);
  }
  if (ref != "CAMERA" && ref != camera)
    n.Fail("a requirement's relation is to the camera: CAMERA" +
           (camera.empty() ? std::string() : " (or " + camera + ")") +
           "; relations between objects belong in LSCENE");
  if (canonical == "facing") return {"facing_angle", 0, amount.value_or(30)};
  if (canonical == "infrontof")
    return {"ahead_of_camera", 0, amount.value_or(kCameraRelationReachM)};
  if (canonical == "behind") return {"ahead_of_camera", -amount.value_or(kCameraRelationReachM), 0};
  if (canonical == "near") return {"distance", 0, amount.value_or(10)};
  if (amount) n.Fail("VISIBLE FROM:CAMERA takes no number");
  return {"visibility", 1e-9, 1};  // some of it seen
}

void ReadBudget(const Definition& d, RequirementSet* set) {
  if (const Node b = d.body.Find("budget")) {
    const double v = ReadInRange(b, KindVocabulary(d.kind).Key("budget"));
    set->budget = std::max(set->budget, static_cast<int>(v));
  }
  if (const Node o = d.body.Find("onbudget")) {
    const std::string v = ReadString(o);
    if (v != "keep" && v != "fail") o.Fail("on_budget is keep (the default) or fail");
    if (v == "fail") set->fail_on_budget = true;
  }
  if (const Node c = d.body.Find("cameras")) {
    const std::string v = ReadString(c);
    if (v != "all" && v != "any") c.Fail("cameras is all (the default) or any");
    if (v == "any") set->rig_any = true;
  }
}

}  // namespace

const std::vector<std::string>& RequirementQuantities() {
  static const std::vector<std::string> all = [] {
    std::vector<std::string> v = TargetQuantities();
    v.insert(v.end(), FrameQuantities().begin(), FrameQuantities().end());
    return v;
  }();
  return all;
}

bool IsFrameQuantity(const std::string& quantity) {
  return std::find(FrameQuantities().begin(), FrameQuantities().end(), quantity) !=
         FrameQuantities().end();
}

bool IsRequirementKind(const std::string& kind) { return kind == "require" || kind == "quota"; }

void CheckRequirementDefinition(const Definition& d) {
  CheckKeys(d.body, KindVocabulary(d.kind), d.kind + " " + d.symbol);
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
  // Relations to the camera, horizontal as LSCENE's: the angle between the
  // target's heading and its direction to the camera (0: it faces the
  // camera), and how far ahead of the camera it lies along the camera's
  // heading (the optical axis on the ground; the image top when looking
  // straight down).
  const Eigen::Vector2d heading = HeadingOf(box.world_from_box);
  const Eigen::Vector2d to_camera_xy = to_camera.head<2>();
  m["facing_angle"] =
      to_camera_xy.norm() > 1e-12
          ? std::acos(std::clamp(heading.dot(to_camera_xy.normalized()), -1.0, 1.0)) * kRadToDeg
          : 0.0;
  const Eigen::Matrix3d world_from_cam = cam_from_world.rotation.conjugate().toRotationMatrix();
  Eigen::Vector2d camera_heading = world_from_cam.col(2).head<2>();
  if (camera_heading.norm() < 1e-6) camera_heading = -world_from_cam.col(1).head<2>();
  m["ahead_of_camera"] = camera_heading.norm() > 1e-12
                             ? (box.center - centre).head<2>().dot(camera_heading.normalized())
                             : 0.0;
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

std::map<std::string, double> FrameMeasures(const Plan& plan, const PlannedFrame& frame) {
  const Rigid3d& cam_from_world = frame.cam_from_world;
  const Eigen::Vector3d c = CameraCenterInWorld(cam_from_world);
  const double ground = plan.terrain.present ? TerrainHeight(plan.terrain, c.x(), c.y()) : 0.0;
  // The optical axis (camera +z) in the world.
  const Eigen::Vector3d axis = cam_from_world.rotation.conjugate() * Eigen::Vector3d::UnitZ();
  std::map<std::string, double> m = {
      {"altitude", c.z() - ground},
      {"off_nadir", std::acos(std::clamp(-axis.z(), -1.0, 1.0)) * kRadToDeg}};
  // The frame's sun (an LCAP change may set it per frame); its clock, when it
  // has one, runs with the frame time.
  const PlannedSun sun = EnvironmentAt(plan, frame).sun;
  m["sun_elevation"] = sun.elevation_deg;
  if (sun.clock_utc_s) {
    const double hours = (*sun.clock_utc_s + frame.time) / 3600.0 + sun.utc_offset_h;
    m["time_of_day"] = hours - 24.0 * std::floor(hours / 24.0);
  }
  return m;
}

FrameMeasure MeasureTruth(const Plan& plan,
                          const PlannedFrame& frame,
                          const std::vector<ObjectTruth>& objects) {
  FrameMeasure m;
  m.frame = FrameMeasures(plan, frame);
  for (const ObjectTruth& o : objects) {
    if (!o.obb) continue;  // the generator's objects all have a 3D box
    TargetMeasure t;
    t.object = o.name;
    t.values = GeometricMeasures(*o.obb, frame.camera, frame.cam_from_world);
    t.values["class"] = o.class_id;
    t.values["in_frame"] = o.in_frame;
    t.values["visibility"] = o.visibility;
    t.values["occlusion"] = 1.0 - o.visibility;
    m.targets.push_back(std::move(t));
  }
  return m;
}

namespace {

// require{...}: its bounds, one per key besides target, budget and cameras.
Requirement ReadRequire(const Definition& d, const std::string& target, const std::string& camera) {
  Requirement r;
  r.name = d.symbol;
  r.target = target;
  for (const auto& [key, node] : d.body.Members()) {
    const std::string k = CanonicalKey(key);
    if (k == "target" || k == "budget" || k == "onbudget" || k == "cameras") continue;
    if (k == "probability" || k == "p") {
      r.probability = ReadInRange(node, KindVocabulary("require").Key("probability"));
      continue;
    }
    if (IsCameraRelation(k)) {
      if (target.empty()) node.FailKey("a relation to the camera needs target:OBJECT");
      r.bounds.push_back(CameraRelationBound(node, k, camera));
      continue;
    }
    const std::string q = QuantityOf(node, key);
    if (q == "class")
      node.FailKey("class is a quota quantity: quota{target:T,quantity:class,classes:{...}}");
    if (!IsFrameQuantity(q) && target.empty())
      node.FailKey("'" + q + "' is a quantity of a target: add target:OBJECT");
    r.bounds.push_back(ReadBound(node, q));
  }
  if (r.bounds.empty()) d.body.Fail("require " + d.symbol + " bounds nothing");
  return r;
}

// A class quota's bins are class names: classes:{car:1,truck:1} (the shares)
// or classes:[car,truck] (equal shares, or weights:[...]).
void ReadClassBins(const Definition& d, Quota* q) {
  const Node bins = d.body.Find("bins"), classes = d.body.Find("classes");
  if (bins) bins.FailKey("a class quota's bins are classes:{name: share, ...}");
  if (!classes || !(classes->is_object() || classes->is_array()) || classes->empty())
    (classes ? classes : d.body)
        .Fail("a class quota needs classes:{name: share, ...} or classes:[name, ...]");
  q->classes_node = classes;
  if (classes->is_object()) {
    if (d.body.Find("weights"))
      d.body.Find("weights").FailKey("the shares are the values of classes:{name: share}");
    for (const auto& [name, share] : classes.Members()) {
      q->classes.push_back(name);
      q->weights.push_back(ReadNumber(share));
      if (q->weights.back() < 0) share.Fail("a share is >= 0");
    }
  } else {
    for (size_t i = 0; i < classes->size(); ++i) q->classes.push_back(ReadString(classes.Item(i)));
  }
  for (size_t i = 0; i < q->classes.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (q->classes[i] == q->classes[j])
        classes.Fail("class '" + q->classes[i] + "' is listed twice");
}

// A quota over a number: bins:[e0, e1, ..., en], edges ascending.
void ReadEdgeBins(const Definition& d, Quota* q) {
  const Node bins = d.body.Find("bins"), classes = d.body.Find("classes");
  if (classes) classes.FailKey("classes belong to a quota over quantity:class");
  if (!bins || !bins->is_array() || bins->size() < 2)
    (bins ? bins : d.body).Fail("a quota needs bins:[e0, e1, ..., en] (n bins, edges ascending)");
  for (size_t i = 0; i < bins->size(); ++i) {
    q->edges.push_back(ReadNumber(bins.Item(i)));
    if (i > 0 && q->edges[i] <= q->edges[i - 1]) bins.Item(i).Fail("bin edges must ascend");
  }
}

// The bins' shares: weights:[...] (or the class shares, or equal), summing to 1.
void ReadQuotaWeights(const Definition& d, Quota* q) {
  const size_t n = q->categorical() ? q->classes.size() : q->edges.size() - 1;
  if (q->weights.empty()) q->weights.assign(n, 1.0);
  if (const Node w = d.body.Find("weights")) {
    if (!w->is_array() || w->size() != n)
      w.Fail("weights:[...] needs one weight per bin (" + std::to_string(n) + ")");
    for (size_t i = 0; i < n; ++i) {
      q->weights[i] = ReadNumber(w.Item(i));
      if (q->weights[i] < 0) w.Item(i).Fail("a weight is >= 0");
    }
  }
  const double sum = std::accumulate(q->weights.begin(), q->weights.end(), 0.0);
  if (sum <= 0) d.body.Fail("the quota's weights sum to 0");
  for (double& w : q->weights) w /= sum;
}

// quota{...}: the quantity, its bins and their weights, tolerance and sampling.
Quota ReadQuota(const Definition& d, const std::string& target) {
  Quota q;
  q.name = d.symbol;
  q.target = target;
  const Node quantity = d.body.Find("quantity");
  if (!quantity)
    d.body.Fail("a quota needs quantity:NAME (" + Join(RequirementQuantities(), ", ") + ")");
  q.quantity = QuantityOf(quantity, ReadString(quantity));
  // A class quota without a target is over every target in view.
  if (!IsFrameQuantity(q.quantity) && q.quantity != "class" && target.empty())
    quantity.Fail("'" + q.quantity + "' is a quantity of a target: add target:OBJECT");
  if (q.quantity == "class") {
    ReadClassBins(d, &q);
  } else {
    ReadEdgeBins(d, &q);
  }
  ReadQuotaWeights(d, &q);
  if (const Node t = d.body.Find("tolerance")) {
    q.tolerance = ReadInRange(t, KindVocabulary("quota").Key("tolerance"));
  }
  if (const Node s = d.body.Find("sampling")) {
    const std::string v = ReadString(s);
    if (v != "importance" && v != "rejection")
      s.Fail("sampling is importance (the default) or rejection");
    q.importance = v == "importance";
  }
  return q;
}

// The paper's allowable occlusion on an LSCENE object (section 4.2): a hard requirement on every
// frame, as require{target:X, occlusion:[lo, hi]}.
void AddObjectOcclusions(const Program& scene, RequirementSet* set) {
  for (const Definition& d : scene.definitions)
    if (d.kind == "object")
      if (const Node n = d.body.Find("occlusion")) {
        Requirement r;
        r.name = d.symbol + ":occlusion";
        r.target = d.symbol;
        r.bounds.push_back(ReadBound(n, "occlusion"));
        if (r.bounds.back().lo < 0 || r.bounds.back().hi > 1)
          n.Fail("occlusion is a share of the object hidden: [min, max] within [0, 1]");
        set->requirements.push_back(r);
      }
}

}  // namespace

RequirementSet ReadRequirements(const Program& capture, const Program& scene) {
  RequirementSet set;
  std::string camera;
  for (const Definition& d : capture.definitions)
    if (d.kind == "camera") camera = d.symbol;
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
      set.requirements.push_back(ReadRequire(d, target, camera));
    } else {
      set.quotas.push_back(ReadQuota(d, target));
    }
  }
  AddObjectOcclusions(scene, &set);
  return set;
}

void ResolveQuotaClasses(const std::vector<ClassInfo>& classes, RequirementSet* set) {
  for (Quota& q : set->quotas) {
    q.class_ids.clear();
    for (const std::string& name : q.classes) {
      const ClassInfo* found = nullptr;
      for (const ClassInfo& c : classes)
        if (c.name == name) found = &c;
      if (!found) {
        std::vector<std::string> names;
        names.reserve(classes.size());
        for (const ClassInfo& c : classes) names.push_back(c.name);
        q.classes_node.Fail("quota " + q.name + ": no class '" + name +
                            "' in the scene or the capture's class swaps" +
                            DidYouMean(name, names) + "; classes: " + Join(names, ", "));
      }
      q.class_ids.push_back(found->id);
    }
  }
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

std::pair<double, double> BinRange(const Quota& quota, int bin) {
  const size_t b = static_cast<size_t>(bin);
  if (quota.categorical()) return {quota.class_ids.at(b), quota.class_ids.at(b)};
  return {quota.edges.at(b), quota.edges.at(b + 1)};
}

int QuotaBin(const Quota& quota, double value) {
  if (quota.categorical()) {
    for (size_t b = 0; b < quota.class_ids.size(); ++b)
      if (quota.class_ids[b] == value) return static_cast<int>(b);
    return -1;
  }
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
  bool half_open;               // a quota bin other than the last: [lo, hi)
  std::string class_name = "";  // a class quota's bin
};

std::vector<Check> ChecksOf(const FrameDemand& demand) {
  std::vector<Check> checks;
  for (const Requirement* r : demand.active)
    for (const Bound& b : r->bounds)
      checks.push_back(
          {r->name, IsFrameQuantity(b.quantity) ? "" : r->target, b.quantity, b.lo, b.hi, false});
  for (const auto& [q, bin] : demand.bins) {
    const auto [lo, hi] = BinRange(*q, bin);
    checks.push_back({q->name,
                      IsFrameQuantity(q->quantity) ? ""
                      : q->target.empty()          ? "*"
                                                   : q->target,
                      q->quantity,
                      lo,
                      hi,
                      !q->categorical() && bin + 2 < static_cast<int>(q->edges.size()),
                      q->categorical() ? q->classes[static_cast<size_t>(bin)] : ""});
  }
  return checks;
}

double Outside(const Check& c, double v) {
  if (v < c.lo) return c.lo - v;
  if (v > c.hi || (c.half_open && v >= c.hi)) return std::max(v - c.hi, 1e-9);
  return 0;
}

// The copies of `symbol` in the measure ("O1#1", "O1#2", ...); "*": every
// target in view.
std::vector<const TargetMeasure*> CopiesOf(const FrameMeasure& m, const std::string& symbol) {
  std::vector<const TargetMeasure*> copies;
  for (const TargetMeasure& t : m.targets)
    if (symbol == "*" || t.object.substr(0, t.object.rfind('#')) == symbol) copies.push_back(&t);
  return copies;
}

// Scale of each quantity so that violations of different units add up (a
// class is right or wrong: 1).
double Scale(const Check& c) { return std::max({1e-6, c.hi - c.lo, std::abs(c.hi) * 0.1}); }

// How far a value misses the check, in units of the check (a wrong class: 1).
double Miss(const Check& c, double v) {
  if (!c.class_name.empty()) return v == c.lo ? 0.0 : 1.0;
  return Outside(c, v) / Scale(c);
}

}  // namespace

double Violation(const FrameDemand& demand, const FrameMeasure& measure) {
  double total = 0;
  for (const Check& c : ChecksOf(demand)) {
    if (c.target.empty()) {
      // A quantity the frame does not have (time_of_day without a clock).
      const auto it = measure.frame.find(c.quantity);
      total += it == measure.frame.end() ? 1.0 : Miss(c, it->second);
      continue;
    }
    const auto copies = CopiesOf(measure, c.target);
    if (copies.empty()) total += 1;  // out of view: every bound fails
    for (const TargetMeasure* t : copies) total += Miss(c, t->values.at(c.quantity));
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
      if (!c.class_name.empty()) j["class"] = c.class_name;
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
      const auto it = measure.frame.find(c.quantity);
      add("", it == measure.frame.end() ? std::nullopt : std::optional<double>(it->second));
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
    if (quota.categorical()) {
      j["classes"] = quota.classes;
      j["class_ids"] = quota.class_ids;
    } else {
      j["bins"] = quota.edges;
    }
    j["sampling"] = quota.importance ? "importance" : "rejection";
    j["weights"] = quota.weights;
    j["tolerance"] = quota.tolerance;
    j["planned"] = planner.PlannedCounts(q);
    quotas.push_back(j);
  }
  return {{"requirements", requirements},
          {"quotas", quotas},
          {"budget", set.budget},
          {"on_budget", set.fail_on_budget ? "fail" : "keep"},
          {"cameras", set.rig_any ? "any" : "all"}};
}

}  // namespace lsds
