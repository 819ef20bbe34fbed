#include "generator/lang/capture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <tuple>

#include "generator/lang/asset_choice.h"
#include "generator/lang/distributions.h"
#include "generator/lang/environment.h"
#include "generator/lang/rig.h"
#include "generator/lang/vocabulary.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/attitude.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// The camera's exposure (docs/languages.md, "Exposure"): `ev100`, or
// `shutter` (s) with `f_number` and `iso` (default 100); neither: auto
// exposure, with `iso` and `f_number` fixed if given.
PlannedExposure ReadExposure(const Node& settings) {
  PlannedExposure e;
  const KindSpec& vocabulary = KindVocabulary("camera_settings");
  auto read = [&](const Node& n, const char* key) { return ReadInRange(n, vocabulary.Key(key)); };
  if (const Node n = settings.Find("iso")) e.iso = read(n, "iso");
  if (const Node n = settings.Find("fnumber")) e.f_number = read(n, "f_number");
  if (const Node n = settings.Find("shutter")) {
    e.shutter_s = read(n, "shutter");
    if (!e.f_number) n.Fail("a manual exposure by shutter needs f_number too (or give ev100)");
  }
  if (const Node n = settings.Find("ev100")) {
    if (e.shutter_s || e.iso || e.f_number)
      n.Fail("give ev100 or shutter, f_number and iso, not both");
    e.ev100 = read(n, "ev100");
  }
  if (const Node n = settings.Find("exposurecompensation"))
    e.compensation_ev = read(n, "exposure_compensation");
  return e;
}

// Default minimum clearance of a camera above the terrain and objects
// (docs/languages.md, "Cameras where a drone can be").
constexpr double kDefaultClearanceM = 1.0;
// The timing keys of a collection entry (vocabulary.h).
std::vector<std::string> TimingKeys() { return KindVocabulary("timing").Spellings(); }

// "P1:3" / "P1" / {"P1": 3} -> (symbol, number or -1).
std::pair<std::string, int64_t> RefWithNumber(const Node& n) {
  if (n->is_object() && n->size() == 1) {
    const auto [key, value] = n.Members().front();
    const double v = ReadNumber(value);
    if (v < 1 || v != std::floor(v) || v > 1e6) value.Fail("expected a whole number >= 1");
    return {key, static_cast<int64_t>(v)};
  }
  const std::string s = ReadString(n);
  const size_t colon = s.find(':');
  if (colon == std::string::npos) return {s, -1};
  const std::string num = s.substr(colon + 1);
  char* end = nullptr;
  const long long v = std::strtoll(num.c_str(), &end, 10);
  if (num.empty() || *end != '\0' || v < 0 || v > 1000000)
    n.Fail("expected NAME:NUMBER, found '" + s + "'");
  return {s.substr(0, colon), static_cast<int64_t>(v)};
}

// The canonical key of a path generator: `increment point` is
// `increment_points`.
std::string PathKind(const std::string& key) {
  const std::string k = CanonicalKey(key);
  return k == "incrementpoint" ? "incrementpoints" : k;
}

// A flight's curve, sampled densely: arc length -> position, the attitude
// interpolated between the waypoints, and the velocity.
struct FlightSample {
  Rigid3d cam_from_world;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();    // the point on the curve
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // world m/s
  Eigen::Vector3d tangent = Eigen::Vector3d::Zero();   // unit direction of travel
};

struct Flight {
  double speed = 0;    // m/s
  double spacing = 0;  // metres between frames: speed / fps
  double length = 0;   // of the curve, metres
  int64_t frame_count = 0;
  std::vector<Eigen::Quaterniond> attitudes;  // cam_from_world at waypoints
  std::vector<Eigen::Vector3d> points;        // dense curve
  std::vector<double> along;                  // arc length at each point
  std::vector<double> param;                  // waypoint parameter (i + t)

  static constexpr int kSamplesPerSegment = 64;

  void Build(const std::vector<Rigid3d>& poses, bool spline) {
    std::vector<Eigen::Vector3d> centres;
    std::vector<Eigen::Quaterniond> rotations;
    for (const Rigid3d& p : poses) {
      centres.push_back(CameraCenterInWorld(p));
      rotations.push_back(p.rotation);
    }
    Build(centres, rotations, spline);
  }

  // The curve through `centres` (an object's path has identity attitudes).
  void Build(const std::vector<Eigen::Vector3d>& centres,
             const std::vector<Eigen::Quaterniond>& rotations,
             bool spline) {
    attitudes = rotations;
    const size_t n = centres.size();
    auto at = [&](size_t i, double t) -> Eigen::Vector3d {
      const Eigen::Vector3d& p1 = centres[i];
      const Eigen::Vector3d& p2 = centres[i + 1];
      if (!spline) return p1 + t * (p2 - p1);
      // Catmull-Rom (uniform), the end points repeated.
      const Eigen::Vector3d& p0 = centres[i == 0 ? 0 : i - 1];
      const Eigen::Vector3d& p3 = centres[std::min(i + 2, n - 1)];
      const double t2 = t * t, t3 = t2 * t;
      return 0.5 * ((2 * p1) + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 +
                    (-p0 + 3 * p1 - 3 * p2 + p3) * t3);
    };
    for (size_t i = 0; i + 1 < n; ++i) {
      for (int k = (i == 0 ? 0 : 1); k <= kSamplesPerSegment; ++k) {
        const double t = static_cast<double>(k) / kSamplesPerSegment;
        const Eigen::Vector3d p = at(i, t);
        along.push_back(points.empty() ? 0.0 : along.back() + (p - points.back()).norm());
        points.push_back(p);
        param.push_back(static_cast<double>(i) + t);
      }
    }
    length = along.back();
  }

  FlightSample At(double s) const {
    s = std::clamp(s, 0.0, length);
    const size_t j =
        static_cast<size_t>(std::upper_bound(along.begin(), along.end(), s) - along.begin());
    const size_t hi = std::clamp<size_t>(j, 1, along.size() - 1), lo = hi - 1;
    const double span = along[hi] - along[lo];
    const double t = span > 0 ? (s - along[lo]) / span : 0.0;
    const Eigen::Vector3d centre = points[lo] + t * (points[hi] - points[lo]);
    const double u = param[lo] + t * (param[hi] - param[lo]);
    const size_t w = std::min(static_cast<size_t>(u), attitudes.size() - 2);
    const Eigen::Quaterniond rotation =
        attitudes[w].slerp(u - static_cast<double>(w), attitudes[w + 1]);
    FlightSample sample;
    sample.cam_from_world.rotation = rotation;
    sample.cam_from_world.translation = -(rotation * centre);
    sample.centre = centre;
    const Eigen::Vector3d d = points[hi] - points[lo];
    sample.tangent = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
    sample.velocity = speed * sample.tangent;
    return sample;
  }
};

struct Segment {
  const Definition* path = nullptr;
  const Definition* collection = nullptr;  // whose move flies it, if any
  int64_t repetition = 1;                  // 1-based
  int64_t first = 0;                       // global frame index of its first frame
  int64_t count = 0;
};

struct Rule {
  std::string object_symbol;     // the object, or the environment symbol
  std::string environment_kind;  // skybox, light, ...: an environment change
  Node block;                    // the change keys
  Node timing;                   // for messages
  bool during = false;
  int64_t begin = 0;                                  // first frame in effect
  int64_t end = std::numeric_limits<int64_t>::max();  // one past the last (during)
  uint64_t id = 0;
  // An object's `move:[P2, P3:2]`: the flights it follows from `begin`, one
  // after the other, each repeated.
  struct Leg {
    const Flight* flight = nullptr;
    int64_t repetitions = 1;
  };
  std::vector<Leg> legs;
  bool heading = false;  // the object turns to its direction of travel
};

class CaptureEvaluator {
 public:
  CaptureEvaluator(const Program& capture, uint64_t seed, Plan* plan)
      : cap_(capture), seed_(seed), plan_(plan) {}

  void Run(int64_t begin, int64_t end) {
    Check();
    ReadCamera();
    BuildTimeline();
    BuildRules();
    std::set<std::string> made_visible;
    for (const Rule& rule : rules_)
      for (const auto& [key, v] : rule.block.Members())
        if (CanonicalKey(key) == "visible" || CanonicalKey(key) == "visibility")
          made_visible.insert(rule.object_symbol);
    DropHelperClasses(made_visible, plan_, swapped_in_);
    ResolveQuotaClasses(plan_->classes, &requirements_);
    // Paths give time steps; a rig has one frame per camera per step.
    const int64_t steps = segments_.empty() ? 0 : segments_.back().first + segments_.back().count;
    const int64_t total = steps * RigSize();
    if (end < 0 || end > total) end = total;
    if (requirements_.empty()) {
      for (int64_t k = std::max<int64_t>(0, begin); k < end; ++k) plan_->frames.push_back(Frame(k));
      return;
    }
    // Requirements and quotas (requirements.h): redraw each frame until the
    // estimate meets its demand, within the budget. With a rig the unit of
    // redraw is the time step: its cameras move together, and the demand
    // holds in every camera (cameras:all) or in one at least (cameras:any).
    const int64_t n = RigSize();
    const DemandPlanner demands(requirements_, seed_, steps);
    plan_->requirements = RequirementsProvenance(requirements_, demands);
    if (plan_->rig) plan_->requirements["unit"] = "step";
    for (int64_t step = std::max<int64_t>(0, begin) / n; step * n < end; ++step)
      for (PlannedFrame& f : RequiredStep(step, demands.For(step)))
        if (f.index >= begin && f.index < end) plan_->frames.push_back(std::move(f));
  }

  RequirementSet requirements_;
  FrameEstimatorFactory estimator_factory_;

 private:
  void Check() {
    int cameras = 0;
    for (const Definition& d : cap_.definitions) {
      if (d.kind == "camera") {
        if (++cameras > 1)
          d.statement.Fail(
              "one camera per capture; several cameras on one platform are a rig: "
              "camera{rig:{left:{position:[-0.1,0,0]},right:{position:[0.1,0,0]}}}");
        camera_ = &d;
        lsds::CheckKeys(d.body, KindVocabulary("camera"), "camera " + d.symbol);
      } else if (d.kind == "path") {
        const KindSpec& path = KindVocabulary("path");
        d.body.CheckKeys(path.Spellings(), "path " + d.symbol);
        if (d.body->size() != 1)
          d.body.Fail("a path has exactly one generator: " + Join(path.Spellings(), ", "));
      } else if (d.kind == "collection" || d.kind == "scene_change") {
      } else if (IsRequirementKind(d.kind)) {
        CheckRequirementDefinition(d);
      } else {
        d.statement.Fail("'" + d.kind + "' belongs in the LSCENE scene file, not in LCAP");
      }
    }
    if (cap_.start_rule) {
      for (size_t i = 0; i < cap_.start_rule->size(); ++i) {
        const Node e = cap_.start_rule.Item(i);
        if (!e->is_object()) e.Fail("expected ONE(...) or MANY(...)");
        e.CheckKeys({"ONE", "MANY", "count"}, "the start rule");
        const Node sym = e.Child("ONE") ? e.Child("ONE") : e.Child("MANY");
        if (!sym) e.Fail("expected ONE(...) or MANY(...)");
        const std::string name = ReadString(sym);
        if (!cap_.Find(name) && !CategoryKinds().count(name)) {
          std::vector<std::string> names;
          for (const Definition& d : cap_.definitions) names.push_back(d.symbol);
          sym.Fail("the start rule names undefined symbol '" + name + "'" +
                   DidYouMean(name, names));
        }
      }
    }
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void ReadCamera() {
    camera_model_ = PinholeCamera::FromHorizontalFov(1024, 1024, 60);
    if (!camera_) return;
    const Node& b = camera_->body;
    IntrinsicSettings intrinsics;
    const KindSpec& camera = KindVocabulary("camera");
    if (const Node settings = FindKey(b, camera, "csettings")) {
      lsds::CheckKeys(settings, KindVocabulary("camera_settings"), "camera settings");
      intrinsics.Read(settings);
      plan_->exposure = ReadExposure(settings);
      camera_model_ = intrinsics.Camera();
      if (const Node f = settings.Find("fps")) {
        fps_ = ReadInRange(f, KindVocabulary("camera_settings").Key("fps"));
      }
      if (const Node h = settings.Find("heights")) {
        const std::string v = ReadString(h);
        if (v != "agl" && v != "datum")
          h.Fail("heights is agl (above the terrain) or datum (world z), not '" + v + "'");
        heights_agl_ = v == "agl";
      }
      if (const Node c = settings.Find("clearance")) {
        if (c->is_string() && ReadString(c) == "off") {
          clearance_.reset();  // the user's explicit opt-out
        } else {
          clearance_ = ReadNumber(c);
          if (!(*clearance_ >= 0) || *clearance_ > 1e4)
            c.Fail("clearance must be a distance in [0, 10000] m, or off");
        }
      }
    }
    // Several cameras on the platform: each frame of the paths becomes one
    // time step with a frame per rig camera (docs/languages.md, "Camera rigs").
    if (const Node r = b.Find("rig")) plan_->rig = ReadRig(r, intrinsics);
    {
      if (const Node n = FindKey(b, camera, "ppmaterial")) {
        if (!n->is_array()) n.Fail("post-process materials are a list [Name, ...]");
        for (size_t i = 0; i < n->size(); ++i) plan_->post_process.push_back(ReadString(n.Item(i)));
      }
    }
    {
      if (const Node n = FindKey(b, camera, "capture")) {
        lsds::CheckKeys(n, KindVocabulary("capture_settings"), "capture settings");
        plan_->capture_settings = nlohmann::json::object();
        if (const Node layers = n.Find("layers")) {
          if (!layers->is_array() || layers->empty())
            layers.Fail("layers is a list of layer names, e.g. [rgb,depth]");
          std::vector<std::string> names;
          const auto& known = StandardLayerSemantics();
          for (size_t i = 0; i < layers->size(); ++i) {
            const std::string name = ReadString(layers.Item(i));
            if (std::find(known.begin(), known.end(), name) == known.end())
              layers.Item(i).Fail("unknown layer '" + name + "'" + DidYouMean(name, known) +
                                  "; layers: " + Join(known, ", "));
            if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
          }
          plan_->capture_settings["layers"] = names;
        }
        for (const char* folder_key : {"folder", "output"})
          if (const Node f = n.Find(folder_key)) {
            const std::string folder = ReadString(f);
            if (folder.empty()) f.Fail("the output folder name is empty");
            plan_->capture_settings["folder"] = folder;
          }
      }
    }
  }

  // A smooth flight (docs/languages.md, "Smooth flights"): `waypoints:{points:
  // [...], speed: m/s, interpolation: linear | spline}` is flown at `speed`,
  // one frame every speed / fps metres along the polyline or a Catmull-Rom
  // spline through the waypoints; the attitude is interpolated (slerp)
  // between the waypoints' attitudes. Waypoint intervals are drawn once per
  // path instance.
  const Flight& FlightOf(const Node& g, uint64_t segment) {
    const auto cached = flights_.find(segment);
    if (cached != flights_.end()) return cached->second;
    Rng rng = Rng::For(seed_, StreamTag::kFlight, segment);
    Flight flight;
    const bool spline = ReadFlightSettings(g, rng, &flight);
    const Node points = g.Find("points");
    std::vector<Rigid3d> poses;
    for (size_t j = 0; j < points->size(); ++j) poses.push_back(WaypointPose(points.Item(j), rng));
    flight.Build(poses, spline);
    const double frames = std::floor(flight.length / flight.spacing + 1e-9) + 1;
    if (frames > 1e6)
      g.Fail("the flight has " + FormatNumber(frames) +
             " frames; lower the fps or raise the speed");
    flight.frame_count = static_cast<int64_t>(frames);
    return flights_.emplace(segment, std::move(flight)).first->second;
  }

  // The keys every flight shares (points, speed, interpolation), checked;
  // fills the speed and spacing and returns whether it is a spline.
  bool ReadFlightSettings(const Node& g, Rng& rng, Flight* flight) const {
    lsds::CheckKeys(g, KindVocabulary("flight"), "waypoints");
    const Node points = g.Find("points"), speed = g.Find("speed");
    if (!points || !points->is_array() || points->size() < 2)
      (points ? points : g).Fail("a flight needs points: at least two waypoints");
    if (!speed) g.Fail("a flight needs a speed (m/s)");
    flight->speed = SampleInRange(speed, KindVocabulary("flight").Key("speed"), rng);
    flight->spacing = flight->speed / fps_;
    if (const Node n = g.Find("interpolation")) {
      const std::string v = ReadString(n);
      if (v != "linear" && v != "spline")
        n.Fail("interpolation is linear or spline, not '" + v + "'");
      return v == "spline";
    }
    return false;
  }

  // The path an object moves along (`O1:{move:[P2]}`): a smooth flight
  // `waypoints:{points:[[x,y,z], ...], speed, interpolation}` through the
  // positions of the object's centre. Its intervals are drawn once per rule
  // and leg (stream (seed, object flight, rule, leg)).
  const Flight& ObjectFlightOf(const Node& item,
                               const Definition& path,
                               uint64_t rule_id,
                               size_t leg) {
    const auto key = std::make_pair(rule_id, leg);
    const auto cached = object_flights_.find(key);
    if (cached != object_flights_.end()) return cached->second;
    const auto [kind, g] = path.body.Members().front();
    if (PathKind(kind) != "waypoints" || !g->is_object())
      item.Fail("an object moves along a smooth flight: '" + path.symbol +
                "' must be path{waypoints:{points:[[x,y,z], ...], speed: "
                "m/s}}");
    Rng rng = Rng::For(seed_, StreamTag::kObjectFlight, rule_id, leg);
    Flight flight;
    const bool spline = ReadFlightSettings(g, rng, &flight);
    const Node points = g.Find("points");
    std::vector<Eigen::Vector3d> centres;
    for (size_t j = 0; j < points->size(); ++j) {
      const Node p = points.Item(j);
      if (!p->is_array() || p->size() != 3)
        p.Fail("an object's waypoint is the position [x,y,z] of its centre");
      centres.push_back(SampleVec3(p, rng));
    }
    flight.Build(centres,
                 std::vector<Eigen::Quaterniond>(centres.size(), Eigen::Quaterniond::Identity()),
                 spline);
    if (!(flight.length > 0)) g.Fail("the path of a moving object has length 0");
    return object_flights_.emplace(key, std::move(flight)).first->second;
  }

  // The number of frames of a path instance; a count interval is drawn from
  // the seed, on the stream of the instance's place `segment` in the timeline.
  int64_t PathFrameCount(const Definition& path, uint64_t segment) {
    Rng count_rng = Rng::For(seed_, StreamTag::kCount, segment);
    const auto [kind, g] = path.body.Members().front();
    const std::string k = PathKind(kind);
    if (k == "createhemi" || k == "hemi") {
      lsds::CheckKeys(g, KindVocabulary("create_hemi"), "create hemi");
      for (const char* key : {"camradius", "objangle", "camangle"})
        if (!g.Find(key))
          g.Fail(
              "create hemi needs cam_radius, obj_angle and cam_angle ([start, "
              "stop, count])");
      return static_cast<int64_t>(ExpandRange(g.Find("camradius")).size() *
                                  ExpandRange(g.Find("objangle")).size() *
                                  ExpandRange(g.Find("camangle")).size());
    }
    if (k == "grid" || k == "incrementpoints") {
      lsds::CheckKeys(g, KindVocabulary("grid"), "grid");
      const auto axes = GridAxes(g);
      return static_cast<int64_t>(axes[0].size() * axes[1].size() * axes[2].size());
    }
    if (k == "random" || k == "randomposes") {
      lsds::CheckKeys(g, KindVocabulary("random"), "random poses");
      if (!g.Find("count")) g.Fail("random poses need a count");
      return SampleCount(g.Find("count"), count_rng);
    }
    if (k == "waypoints") {
      if (g->is_object()) return FlightOf(g, segment).frame_count;
      if (!g->is_array() || g->empty()) g.Fail("waypoints are a non-empty list");
      return static_cast<int64_t>(g->size());
    }
    lsds::CheckKeys(g, KindVocabulary("create_point"), "create point");
    if (!g.Find("position")) g.Fail("create point needs a position");
    if (const Node c = g.Find("count")) return SampleCount(c, count_rng);
    return 1;
  }

  // Grid axes: x and y positions and altitudes above the terrain.
  std::array<std::vector<double>, 3> GridAxes(const Node& g) {
    std::array<std::vector<double>, 3> axes;
    if (g.Find("x") || g.Find("y")) {
      if (!g.Find("x") || !g.Find("y") || !g.Find("altitude"))
        g.Fail("a grid needs x, y and altitude ranges [start, stop, count]");
      axes[0] = ExpandRange(g.Find("x"));
      axes[1] = ExpandRange(g.Find("y"));
      axes[2] = ExpandRange(g.Find("altitude"));
      return axes;
    }
    const Node start = g.Find("start"), step = g.Find("step"), count = g.Find("count");
    if (!start || !step || !count)
      g.Fail(
          "increment points need start [x,y,z], step [dx,dy,dz] and count "
          "[nx,ny,nz]");
    Rng dummy(0);
    const Eigen::Vector3d s = SampleVec3(start, dummy), d = SampleVec3(step, dummy),
                          n = SampleVec3(count, dummy);
    for (int i = 0; i < 3; ++i) {
      if (n[i] < 1 || n[i] > 100000 || n[i] != std::floor(n[i]))
        count.Fail("counts must be whole numbers >= 1");
      for (int j = 0; j < static_cast<int>(n[i]); ++j) axes[i].push_back(s[i] + j * d[i]);
    }
    return axes;
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void BuildTimeline() {
    std::vector<const Definition*> collections;
    for (const Definition& d : cap_.definitions)
      if (d.kind == "collection") collections.push_back(&d);
    const Definition* current_collection = nullptr;
    auto append = [&](const Definition* path, int64_t repetitions) {
      for (int64_t r = 1; r <= repetitions; ++r) {
        Segment s;
        s.path = path;
        s.repetition = r;
        s.first = segments_.empty() ? 0 : segments_.back().first + segments_.back().count;
        s.count = PathFrameCount(*path, segments_.size());
        s.collection = current_collection;
        segments_.push_back(s);
      }
    };
    bool moved = false;
    for (const Definition* c : collections) {
      current_collection = c;
      for (const auto& [key, value] : c->body.Members()) {
        if (!IsCameraEntry(key, value)) continue;
        for (const Node& block : Blocks(value)) {
          block.CheckKeys({"move"}, "camera entry of " + c->symbol);
          const Node move = block.Find("move");
          if (!move) block.Fail("a camera entry needs move:[P1:3, ...]");
          std::vector<Node> items;
          if (move->is_array())
            for (size_t i = 0; i < move->size(); ++i) items.push_back(move.Item(i));
          else
            items.push_back(move);
          for (const Node& item : items) {
            const auto [symbol, reps] = RefWithNumber(item);
            const Definition* path = cap_.Find(symbol);
            if (!path || path->kind != "path")
              item.Fail("'" + symbol + "' is not a path" + DidYouMean(symbol, PathNames()));
            append(path, reps < 0 ? 1 : reps);
            moved = true;
          }
        }
      }
    }
    if (!moved)
      for (const Definition& d : cap_.definitions)
        if (d.kind == "path") append(&d, 1);
  }

  std::vector<std::string> PathNames() const {
    std::vector<std::string> names;
    for (const Definition& d : cap_.definitions)
      if (d.kind == "path") names.push_back(d.symbol);
    return names;
  }

  // The camera's entry in a collection: its symbol, or (the paper writes "C1"
  // for camera "CO") any undefined name whose block moves the camera.
  bool IsCameraEntry(const std::string& key, const Node& value) const {
    if (camera_ && key == camera_->symbol) return true;
    if (cap_.Find(key) || HasObject(key)) return false;
    for (const Node& b : Blocks(value))
      if (b->is_object() && b.Find("move")) return true;
    return false;
  }

  bool HasObject(const std::string& symbol) const {
    for (const PlannedObject& o : plan_->objects)
      if (o.symbol == symbol) return true;
    return scene_symbols_.count(symbol) > 0;
  }

  static std::vector<Node> Blocks(const Node& value) {
    std::vector<Node> blocks;
    if (value->is_array())
      for (size_t i = 0; i < value->size(); ++i) blocks.push_back(value.Item(i));
    else
      blocks.push_back(value);
    return blocks;
  }

  // Frame range of path instance "P1:i" (i < 0: all instances).
  std::pair<int64_t, int64_t> Span(const Node& where,
                                   const std::string& symbol,
                                   int64_t rep) const {
    int64_t lo = -1, hi = -1;
    const Definition* named = cap_.Find(symbol);
    if (named && named->kind == "collection") {
      // A set/collection: the frames of the paths its camera moves fly.
      if (rep >= 0) where.Fail("a collection has no repetitions: write '" + symbol + "'");
      for (const Segment& s : segments_) {
        if (s.collection != named) continue;
        if (lo < 0) lo = s.first;
        hi = s.first + s.count;
      }
      if (lo < 0) where.Fail("collection '" + symbol + "' moves the camera along no path");
      return {lo, hi};
    }
    for (const Segment& s : segments_) {
      if (s.path->symbol != symbol || (rep >= 0 && s.repetition != rep)) continue;
      if (lo < 0) lo = s.first;
      hi = s.first + s.count;
    }
    if (lo < 0) {
      std::vector<std::string> names = PathNames();
      if (cap_.Find(symbol) && rep >= 0)
        where.Fail("path '" + symbol + "' has no repetition " + std::to_string(rep) +
                   " in the camera's moves");
      where.Fail("'" + symbol + "' is not a path the camera moves along" +
                 DidYouMean(symbol, names));
    }
    return {lo, hi};
  }

  static int64_t FrameNumber(const Node& v) {
    const double f = ReadNumber(v);
    if (f < 0 || f != std::floor(f) || f > 1e9) v.Fail("a frame number is a whole number >= 0");
    return static_cast<int64_t>(f);
  }

  void Timing(const Node& block, Rule* rule) {
    for (const auto& [key, v] : block.Members()) {
      const std::string k = CanonicalKey(key);
      if (k == "when") {
        if (v->is_number()) {
          rule->begin = static_cast<int64_t>(ReadNumber(v));
        } else {
          v.CheckKeys({"after", "during", "frame"}, "when");
          Timing(v, rule);
        }
      } else if (k == "after") {
        if (v->is_number()) {  // after frame N: from frame N + 1 on
          rule->begin = FrameNumber(v) + 1;
        } else {
          const auto [symbol, rep] = RefWithNumber(v);
          rule->begin = Span(v, symbol, rep).second;
        }
      } else if (k == "during") {
        if (v->is_number()) {  // during frame N: that frame only
          rule->begin = FrameNumber(v);
          rule->end = rule->begin + 1;
        } else {
          const auto [symbol, rep] = RefWithNumber(v);
          std::tie(rule->begin, rule->end) = Span(v, symbol, rep);
        }
        rule->during = true;
      } else if (k == "frame") {
        const double f = ReadNumber(v);
        if (f < 0 || f != std::floor(f)) v.Fail("frame must be a whole number >= 0");
        rule->begin = static_cast<int64_t>(f);
      }
    }
  }

  void AddRules(const std::string& object,
                const Node& block,
                const Node& timing_block,
                const std::string& where) {
    std::vector<std::string> keys = KindVocabulary("object_change").Spellings();
    const std::vector<std::string> timing = TimingKeys();
    keys.insert(keys.end(), timing.begin(), timing.end());
    const auto environment = environment_symbols_.find(object);
    if (environment != environment_symbols_.end()) {
      // Any LSCENE function of the sky, light, atmosphere, skylight or
      // terrain material, as in the scene (docs/languages.md).
      std::vector<std::string> env_keys = EnvironmentKeys(environment->second, true);
      env_keys.insert(env_keys.end(), timing.begin(), timing.end());
      block.CheckKeys(env_keys, where);
      Rule rule;
      rule.object_symbol = object;
      rule.environment_kind = environment->second;
      rule.block = block;
      rule.timing = timing_block;
      rule.id = rules_.size() + 1;
      Timing(timing_block, &rule);
      Rng probe(0);  // bad values are reported now, not on some frame
      PlannedEnvironment scratch = EnvironmentOf(*plan_);
      ApplyEnvironment(rule.environment_kind, block, probe, &scratch);
      if (scratch.sun.clock_utc_s && !plan_->geo)
        block.Fail(
            "a sun given by date and time needs a place: add a "
            "georeference{latitude, longitude, altitude} to the scene");
      rules_.push_back(rule);
      return;
    }
    block.CheckKeys(keys, where);
    if (!HasObject(object)) {
      std::vector<std::string> names(scene_symbols_.begin(), scene_symbols_.end());
      block.Fail("'" + object + "' is not an object of the scene" + DidYouMean(object, names));
    }
    Rule rule;
    rule.object_symbol = object;
    rule.block = block;
    rule.timing = timing_block;
    rule.id = rules_.size() + 1;
    Timing(timing_block, &rule);
    ReadMotion(block, &rule);
    if (const Node cls = block.Find("class")) {
      if (!cls->is_string() && !cls->is_object())
        cls.Fail("class must be a name or a choice {name: weight}");
      for (const std::string& option : SwapOptions(cls))
        for (const SceneClass& candidate : SwapCandidates(cls, option))
          swapped_in_.insert(SwapClass(object, candidate).second);
    }
    // Sample once with a throwaway stream so that bad values are reported now,
    // not on some frame.
    Rng probe(0);
    for (const PlannedObject& o : plan_->objects)
      if (o.symbol == object) {
        Change(rule, o, probe);
        break;
      }
    rules_.push_back(rule);
  }

  // `move:[P2, P3:2]` and `heading` of an object's change block; `rescatter`
  // is checked here too (it draws a new position, a move follows a path).
  void ReadMotion(const Node& block, Rule* rule) {
    const Node move = block.Find("move");
    if (const Node h = block.Find("heading")) {
      if (!move) h.Fail("heading turns an object along its move; add move:[P]");
      if (!h->is_boolean()) h.Fail("heading is true or false");
      rule->heading = h->get<bool>();
    }
    if (const Node r = block.Find("rescatter")) {
      if (!r->is_boolean()) r.Fail("rescatter is true or false");
      if (move) r.Fail("an object either moves along a path or is re-scattered");
    }
    if (!move) return;
    if (const Node n = block.Find("offset"))
      n.Fail(
          "a moving object's position comes from its path; offset it in "
          "another block");
    std::vector<Node> items;
    if (move->is_array())
      for (size_t i = 0; i < move->size(); ++i) items.push_back(move.Item(i));
    else
      items.push_back(move);
    if (items.empty()) move.Fail("move lists paths: move:[P2, P3:2]");
    for (const Node& item : items) {
      const auto [symbol, reps] = RefWithNumber(item);
      const Definition* path = cap_.Find(symbol);
      if (!path || path->kind != "path")
        item.Fail("'" + symbol + "' is not a path" + DidYouMean(symbol, PathNames()));
      Rule::Leg leg;
      leg.flight = &ObjectFlightOf(item, *path, rule->id, rule->legs.size());
      leg.repetitions = reps < 0 ? 1 : reps;
      rule->legs.push_back(leg);
    }
  }

  // The options of a class change: its names or choice keys, or "tags" for a
  // library tag selection (`class:{tags:[desert,rock]}`).
  static std::vector<std::string> SwapOptions(const Node& cls) {
    if (IsTagSelection(cls)) return {"tags"};
    return StringOptions(cls);
  }

  // What option `option` of class node `cls` may draw: the scene's asset
  // library's assets it selects (by name, tags or pattern, as in LSCENE), or
  // else the one class it resolves to.
  std::vector<SceneClass> SwapCandidates(const Node& cls, const std::string& option) {
    std::vector<SceneClass> out;
    for (const gen::LibraryAsset* a : SelectAssets(Library(), cls, option))
      out.push_back({a->file, AssetClassName(*a)});
    if (out.empty()) out.push_back(ResolveSceneClass(*scene_, cls, option));
    return out;
  }

  // The scene's asset_library, loaded once (null when it has none).
  const gen::AssetLibrary* Library() {
    if (!library_loaded_) {
      library_loaded_ = true;
      for (const Definition& d : scene_->definitions)
        if (d.kind == "asset_library") library_ = LoadSceneAssetLibrary(*scene_, d);
    }
    return library_ ? &*library_ : nullptr;
  }

  // The asset and class id a class change draws for an object of `symbol`:
  // a labelled target keeps its label; another object takes the class of
  // that name, added to the class table if the scene has none (after the
  // scene's ids, so that the scene's ids never change).
  std::pair<std::string, uint32_t> SwapClass(const std::string& symbol,
                                             const SceneClass& resolved) {
    const auto label = labels_.find(symbol);
    if (label != labels_.end() && label->second != 0) return {resolved.asset, label->second};
    uint32_t next = 1;
    for (const ClassInfo& c : plan_->classes) {
      if (c.name == resolved.name) return {resolved.asset, c.id};
      next = std::max(next, c.id + 1);
    }
    for (const auto& [s, l] : labels_) next = std::max(next, l + 1);
    plan_->classes.push_back({next, resolved.name});
    return {resolved.asset, next};
  }

  void BuildRules() {
    for (const Definition& d : cap_.definitions) {
      if (d.kind != "collection") continue;
      for (const auto& [key, value] : d.body.Members()) {
        if (IsCameraEntry(key, value)) continue;
        const Definition* set = cap_.Find(key);
        for (const Node& block : Blocks(value)) {
          if (!block->is_object()) block.Fail("expected {when:{...}, change...} for " + key);
          if (set && set->kind == "scene_change") {  // SCS1:{after:P1:1} applies the
                                                     // set with that timing
            block.CheckKeys(TimingKeys(), "scene change set entry " + key);
            for (const auto& [object, changes] : set->body.Members())
              for (const Node& change : Blocks(changes))
                AddRules(object, change, block, "scene change set " + key);
          } else if (set) {
            block.Fail("'" + key + "' is a " + set->kind +
                       "; a collection entry names the camera, an object or a "
                       "scene change set");
          } else {
            AddRules(key, block, block, "scene change of " + key);
          }
        }
      }
    }
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  ObjectChange Change(const Rule& rule, const PlannedObject& o, Rng& rng) {
    ObjectChange c;
    c.object = o.name;
    for (const auto& [key, v] : rule.block.Members()) {
      const std::string k = CanonicalKey(key);
      if (k == "material") c.material = SampleString(v, rng);
      if (k == "rotation") c.world_from_object = RotationFromEulerDeg(SampleVec3(v, rng));
      if (k == "visible" || k == "visibility") c.visible = SampleBool(v, rng);
      if (k == "extent") {
        c.extent = SampleVec3(v, rng);
        if (c.extent->minCoeff() <= 0) v.Fail("extent components must be > 0");
      }
      if (k == "scale") {
        const Eigen::Vector3d s = SampleScale(v, rng);
        if (s.minCoeff() <= 0) v.Fail("scale must be > 0");
        c.extent = o.extent.cwiseProduct(s);
      }
      if (k == "offset") c.position = o.position + SampleVec3(v, rng);
      if (k == "class") {
        std::string option = IsTagSelection(v) ? std::string("tags") : SampleString(v, rng);
        // Importance sampling of a class quota: the option of the frame's
        // class bin, when the swap can draw it (a name that resolves to one
        // class, not a library selection of several).
        if (const auto bin = DemandedBin("class", o); bin && !IsTagSelection(v)) {
          for (const std::string& candidate : StringOptions(v)) {
            const std::vector<SceneClass> resolved = SwapCandidates(v, candidate);
            if (resolved.size() == 1 && SwapClass(o.symbol, resolved[0]).second == bin->first)
              option = candidate;
          }
        }
        // A library selection draws one of its assets, uniformly.
        const std::vector<SceneClass> candidates = SwapCandidates(v, option);
        const SceneClass& drawn = candidates.size() == 1
                                      ? candidates[0]
                                      : candidates[static_cast<size_t>(rng.UniformInt(
                                            0, static_cast<int64_t>(candidates.size()) - 1))];
        const auto [asset, id] = SwapClass(o.symbol, drawn);
        c.asset = asset;
        c.class_id = id;
      }
    }
    return c;
  }

  Eigen::Vector3d ObjectCenter(const Node& where, const std::string& symbol) const {
    for (const PlannedObject& o : plan_->objects)
      if (o.symbol == symbol) return o.position;
    where.Fail("'" + symbol + "' is not a placed object of the scene");
  }

  Eigen::Vector3d Point(const Node& n, Rng& rng) const {
    if (n->is_string()) return ObjectCenter(n, ReadString(n));
    return SampleVec3(n, rng);
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  Rigid3d Pose(const Definition& path,
               int64_t i,
               Rng& rng,
               uint64_t segment = 0,
               std::optional<Eigen::Vector3d>* velocity = nullptr) {
    const auto [kind, g] = path.body.Members().front();
    const std::string k = PathKind(kind);
    const double deg = M_PI / 180.0;
    if (k == "createhemi" || k == "hemi") {
      const auto radii = ExpandRange(g.Find("camradius")), az = ExpandRange(g.Find("objangle")),
                 el = ExpandRange(g.Find("camangle"));
      const size_t a = static_cast<size_t>(i) % az.size();
      const size_t e = (static_cast<size_t>(i) / az.size()) % el.size();
      const size_t r = static_cast<size_t>(i) / (az.size() * el.size());
      Eigen::Vector3d center = Eigen::Vector3d::Zero();
      const Node c = FindKey(g, KindVocabulary("create_hemi"), "center");
      if (c)
        center = Point(c, rng);
      else if (!first_target_.empty())
        center = ObjectCenter(camera_->body, first_target_);
      const Eigen::Vector3d eye =
          center + radii[r] * Eigen::Vector3d(std::cos(el[e] * deg) * std::cos(az[a] * deg),
                                              std::cos(el[e] * deg) * std::sin(az[a] * deg),
                                              std::sin(el[e] * deg));
      return LookAt(eye, center);
    }
    if (k == "grid" || k == "incrementpoints") {
      const auto axes = GridAxes(g);
      const size_t nx = axes[0].size(), ny = axes[1].size();
      const size_t z = static_cast<size_t>(i) / (nx * ny);
      const size_t y = (static_cast<size_t>(i) / nx) % ny;
      size_t x = static_cast<size_t>(i) % nx;
      if (y % 2 == 1) x = nx - 1 - x;  // serpentine (lawnmower) order
      Eigen::Vector3d p(axes[0][x], axes[1][y], axes[2][z]);
      if (const Node n = g.Find("perturb")) {
        const Eigen::Vector3d amp = SampleVec3(n, rng);
        for (int j = 0; j < 3; ++j) p[j] += rng.Uniform(-amp[j], amp[j]);
      }
      p.z() += TerrainHeight(plan_->terrain, p.x(), p.y());
      Attitude att{0, -90, 0};
      if (const Node n = g.Find("roll")) att.roll_deg = SampleScalar(n, rng);
      if (const Node n = g.Find("pitch")) att.pitch_deg = SampleScalar(n, rng);
      if (const Node n = g.Find("yaw")) att.yaw_deg = SampleScalar(n, rng);
      return CamFromEnu(p, att);
    }
    if (k == "random" || k == "randomposes") {
      const Eigen::Vector2d half = plan_->terrain.present
                                       ? Eigen::Vector2d(0.5 * plan_->terrain.size)
                                       : Eigen::Vector2d(50, 50);
      Eigen::Vector3d p(rng.Uniform(-half.x(), half.x()), rng.Uniform(-half.y(), half.y()), 50);
      if (const Node n = g.Find("x")) p.x() = SampleScalar(n, rng);
      if (const Node n = g.Find("y")) p.y() = SampleScalar(n, rng);
      if (const Node n = g.Find("altitude")) p.z() = SampleWithinBin(n, "altitude", rng);
      p.z() += TerrainHeight(plan_->terrain, p.x(), p.y());
      double off_nadir = 0, yaw = rng.Uniform(0, 360);
      if (const Node n = g.Find("offnadir")) off_nadir = SampleWithinBin(n, "off_nadir", rng);
      if (const Node n = g.Find("yaw")) yaw = SampleScalar(n, rng);
      if (const Node n = g.Find("offnadir"))
        CheckRange(n, KindVocabulary("random").Key("off_nadir"), off_nadir);
      return CamFromEnu(p, Attitude{0, -90 + off_nadir, yaw});
    }
    if (k == "waypoints" && g->is_object()) {
      const Flight& flight = FlightOf(g, segment);
      const FlightSample at = flight.At(static_cast<double>(i) * flight.spacing);
      if (velocity) *velocity = at.velocity;
      return at.cam_from_world;
    }
    if (k == "waypoints") return WaypointPose(g.Item(static_cast<size_t>(i)), rng);
    return PointPose(g, rng);
  }

  // A rig camera's velocity on a smooth flight: the platform's velocity plus
  // the lever arm turning with the attitude, by a central difference of the
  // camera centre along the curve.
  Eigen::Vector3d RigCameraVelocity(const Segment& seg, int64_t i, const Rigid3d& cam_from_rig) {
    const auto [kind, g] = seg.path->body.Members().front();
    const Flight& flight = FlightOf(g, static_cast<uint64_t>(&seg - segments_.data()));
    const double s = static_cast<double>(i) * flight.spacing;
    const double h = std::min(0.01, 0.5 * flight.length);
    const double lo = std::max(0.0, s - h), hi = std::min(flight.length, s + h);
    if (!(hi > lo)) return Eigen::Vector3d::Zero();
    auto centre = [&](double at) {
      return CameraCenterInWorld(cam_from_rig * flight.At(at).cam_from_world);
    };
    return (centre(hi) - centre(lo)) * (flight.speed / (hi - lo));
  }

  // The first frame of the shot of pose `i` of a path instance starting at
  // frame `first` (docs/format.md, "Motion"): waypoints are flown in one shot,
  // a grid in one shot per altitude level (its rows are flown serpentine, the
  // climb to the next level is a jump); every pose of hemi, random and
  // create point is a shot of its own.
  int64_t ShotStart(const Definition& path, int64_t first, int64_t i) {
    const auto [kind, g] = path.body.Members().front();
    const std::string k = PathKind(kind);
    if (k == "waypoints") return first;
    if (k == "grid" || k == "incrementpoints") {
      const auto axes = GridAxes(g);
      const int64_t level = static_cast<int64_t>(axes[0].size() * axes[1].size());
      return first + (i / level) * level;
    }
    return first + i;
  }

  // {position, rotation|attitude: [roll,pitch,yaw] | look_at: [x,y,z] or an
  // object}
  // One waypoint: [x,y,z] (nadir), [x,y,z,roll,pitch,yaw] or {position,
  // attitude | look_at}.
  Rigid3d WaypointPose(const Node& w, Rng& rng) const {
    if (w->is_array()) {
      if (w->size() != 3 && w->size() != 6)
        w.Fail("a waypoint is [x,y,z] (nadir) or [x,y,z,roll,pitch,yaw]");
      std::vector<double> v;
      for (size_t j = 0; j < w->size(); ++j) v.push_back(SampleScalar(w.Item(j), rng));
      const Attitude att = v.size() == 6 ? Attitude{v[3], v[4], v[5]} : Attitude{0, -90, 0};
      return CamFromEnu(Datum({v[0], v[1], v[2]}), att);
    }
    lsds::CheckKeys(w, KindVocabulary("waypoint"), "waypoint");
    return PointPose(w, rng);
  }

  // A waypoint or point position in the world frame: with camera settings
  // `heights:agl`, its z is above the terrain under it.
  Eigen::Vector3d Datum(Eigen::Vector3d p) const {
    if (heights_agl_) p.z() += TerrainHeight(plan_->terrain, p.x(), p.y());
    return p;
  }

  Rigid3d PointPose(const Node& g, Rng& rng) const {
    const Node pos = g.Find("position");
    if (!pos) g.Fail("expected a position");
    const Eigen::Vector3d p = Datum(SampleVec3(pos, rng));
    if (const Node l = g.Find("lookat")) return LookAt(p, Point(l, rng));
    Attitude att{0, -90, 0};
    if (const Node r = FindKey(g, KindVocabulary("create_point"), "rotation")) {
      const Eigen::Vector3d rpy = SampleVec3(r, rng);
      att = Attitude{rpy.x(), rpy.y(), rpy.z()};
    }
    return CamFromEnu(p, att);
  }

  // Importance sampling (docs/languages.md, "Requirements and quotas"): the
  // bin [lo, hi] the frame being drawn must hit in a quota over `quantity`
  // with sampling:importance, if any. For a target quantity, only a quota on
  // `object`'s symbol (or, for class, on every target) counts. Depends only on
  // the frame's demand, so draws stay functions of (seed, frame, frame count).
  std::optional<std::pair<double, double>> DemandedBin(
      const std::string& quantity, const PlannedObject* object = nullptr) const {
    if (!demand_) return std::nullopt;
    for (const auto& [q, bin] : demand_->bins) {
      if (!q->importance || q->quantity != quantity) continue;
      if (object && !(q->target == object->symbol || (q->target.empty() && object->target)))
        continue;
      auto range = BinRange(*q, bin);
      // A bin other than the last excludes its upper edge.
      if (!q->categorical() && bin + 2 < static_cast<int>(q->edges.size()))
        range.second = std::nextafter(range.second, -std::numeric_limits<double>::infinity());
      return range;
    }
    return std::nullopt;
  }
  std::optional<std::pair<double, double>> DemandedBin(const std::string& quantity,
                                                       const PlannedObject& object) const {
    return DemandedBin(quantity, &object);
  }

  // A path's scalar that sets a frame quantity (a random pose's altitude
  // above the terrain or off-nadir angle), drawn within the frame's bin when
  // a quota asks for importance sampling of it.
  double SampleWithinBin(const Node& n, const std::string& quantity, Rng& rng) const {
    if (const auto bin = DemandedBin(quantity))
      if (const auto v = SampleScalarWithin(n, bin->first, bin->second, rng)) return *v;
    return SampleScalar(n, rng);
  }

  int64_t RigSize() const {
    return plan_->rig ? static_cast<int64_t>(plan_->rig->cameras.size()) : 1;
  }

  // The frames of time step `step` (one per rig camera; the frame itself
  // without a rig), drawn until the estimate meets the demand in every camera
  // (or, with cameras:any, in one), within the budget; else the draw that came
  // closest (the smallest violation: summed over the cameras, or the least of
  // them with cameras:any).
  std::vector<PlannedFrame> RequiredStep(int64_t step, const FrameDemand& demand) {
    const int64_t n = RigSize();
    auto draw = [&](int attempt) {
      std::vector<PlannedFrame> frames;
      for (int64_t c = 0; c < n; ++c) frames.push_back(Frame(step * n + c, attempt));
      return frames;
    };
    if (demand.active.empty() && demand.bins.empty()) return draw(0);
    if (!estimator_) {
      if (!estimator_factory_)
        throw Error(
            "this capture has requirements or quotas, which need the generator's estimator "
            "(lsds plan / lsds generate)");
      estimator_ = estimator_factory_();
    }
    std::vector<PlannedFrame> best;
    std::vector<FrameMeasure> best_measures;
    double best_violation = 0;
    int attempts = 0;
    std::optional<Error> unplaceable;  // a draw the camera cannot take (clearance)
    demand_ = &demand;
    for (int attempt = 0; attempt <= requirements_.budget; ++attempt) {
      std::vector<PlannedFrame> frames;
      try {
        frames = draw(attempt);
      } catch (const Error& e) {
        // A draw where the drone cannot be is rejected like one that misses
        // the requirements; only when every draw is, the error stands.
        ++attempts;
        if (!unplaceable) unplaceable = e;
        continue;
      }
      std::vector<FrameMeasure> measures;
      double violation = 0;
      for (size_t c = 0; c < frames.size(); ++c) {
        FrameMeasure m = estimator_(*plan_, frames[c]);
        m.frame = FrameMeasures(*plan_, frames[c]);
        const double v = Violation(demand, m);
        violation = c == 0 ? v : requirements_.rig_any ? std::min(violation, v) : violation + v;
        measures.push_back(std::move(m));
      }
      ++attempts;
      if (best.empty() || violation < best_violation) {
        best = std::move(frames);
        best_measures = std::move(measures);
        best_violation = violation;
      }
      if (violation == 0) break;
    }
    demand_ = nullptr;
    if (best.empty()) throw *unplaceable;
    for (size_t c = 0; c < best.size(); ++c) {
      PlannedFrame& f = best[c];
      f.requirements = DemandRecord(demand, best_measures[c]);
      (*f.requirements)["attempts"] = attempts;
      if (plan_->rig) {
        // The step is the unit: the report counts it once.
        (*f.requirements)["step"] = step;
        (*f.requirements)["step_met"] = best_violation == 0;
      }
    }
    if (best_violation > 0 && requirements_.fail_on_budget)
      throw Error(
          (plan_->rig ? "step " + std::to_string(step) + " (frames " + std::to_string(step * n) +
                            "-" + std::to_string(step * n + n - 1) + ")"
                      : "frame " + std::to_string(step)) +
              ": no draw met the requirements in " + std::to_string(attempts) +
              " attempts (budget " + std::to_string(requirements_.budget) +
              "): " + best.front().requirements->at("checks").dump(),
          cap_.definitions.empty() ? Location{} : cap_.definitions.front().statement.Where());
    return best;
  }

  // Frame k's draw number `attempt`: the first from the frame's own streams,
  // redraws from streams of (seed, redraw, attempt), so that every draw still
  // depends only on the seed and k.
  uint64_t FrameSeed(int attempt) const {
    return attempt == 0 ? seed_
                        : MixKey(MixKey(seed_, static_cast<uint64_t>(StreamTag::kRedraw)),
                                 static_cast<uint64_t>(attempt));
  }

  FrameEstimator estimator_;
  const FrameDemand* demand_ = nullptr;  // of the frame being drawn (importance sampling)

  // Frame k: time step k / n of the paths, seen by rig camera k % n (n = 1
  // without a rig, so that the step is the frame). Everything drawn is keyed
  // by the step, so the cameras of one step see one world.
  PlannedFrame Frame(int64_t frame_index, int attempt = 0) {
    const int64_t n = RigSize();
    const int64_t k = frame_index / n;  // the time step
    const int64_t c = frame_index % n;  // the rig camera
    const Segment* seg = nullptr;
    for (const Segment& s : segments_)
      if (k >= s.first && k < s.first + s.count) seg = &s;
    PlannedFrame f;
    f.index = frame_index;
    f.time = static_cast<double>(k) / fps_;
    f.sequence = seg->path->symbol + "(" + std::to_string(seg->repetition) + ")";
    f.shot = ShotStart(*seg->path, seg->first, k - seg->first) * n + c;
    f.camera = camera_model_;
    const uint64_t frame_seed = FrameSeed(attempt);
    Rng rng = Rng::For(frame_seed, StreamTag::kFrame, static_cast<uint64_t>(k));
    f.cam_from_world = Pose(*seg->path,
                            k - seg->first,
                            rng,
                            static_cast<uint64_t>(seg - segments_.data()),
                            &f.camera_velocity);
    if (plan_->rig) {
      const RigCamera& camera = plan_->rig->cameras[static_cast<size_t>(c)];
      const Rigid3d rig_from_world = f.cam_from_world;
      f.rig_camera = camera.name;
      f.step = k;
      f.camera = camera.intrinsics;
      f.cam_from_world = camera.cam_from_rig * rig_from_world;
      if (f.camera_velocity)
        f.camera_velocity = RigCameraVelocity(*seg, k - seg->first, camera.cam_from_rig);
    }
    CheckClearance(*seg, k, f, f.cam_from_world);
    std::vector<const Rule*> change_rules;  // the rule of each change
    for (const Rule& rule : rules_) {
      if (k < rule.begin || k >= rule.end) continue;
      // An "after" change is drawn once, when it fires; a "during" change on
      // every frame.
      Rng change_rng =
          rule.during
              ? Rng::For(frame_seed, StreamTag::kFrame, static_cast<uint64_t>(k), rule.id)
              : Rng::For(seed_, StreamTag::kChange, rule.id, static_cast<uint64_t>(rule.begin));
      if (!rule.environment_kind.empty()) {
        if (!f.environment) f.environment = EnvironmentOf(*plan_);
        ApplyEnvironment(rule.environment_kind, rule.block, change_rng, &*f.environment);
        continue;
      }
      const bool rescatter =
          rule.block.Find("rescatter") && rule.block.Find("rescatter")->get<bool>();
      for (const PlannedObject& o : plan_->objects)
        if (o.symbol == rule.object_symbol) {
          ObjectChange change = Change(rule, o, change_rng);
          if (!rule.legs.empty()) Move(rule, o, k, &change);
          if (rescatter) Rescatter(rule, o, f, change_rng, &change);
          f.changes.push_back(change);
          change_rules.push_back(&rule);
        }
    }
    KeepPlacement(change_rules, &f);
    // A sun given by date and time moves with the frame's time.
    if (plan_->geo) {
      PlannedEnvironment environment = EnvironmentAt(*plan_, f);
      if (environment.sun.clock_utc_s) {
        PlaceSun(*plan_->geo, f.time, &environment.sun);
        if (!(environment == EnvironmentOf(*plan_))) f.environment = environment;
      }
    }
    return f;
  }

  // An object moving along its legs (docs/languages.md, "Objects that
  // move"): at time t since the rule began it is where its path is after
  // t * speed metres; after the last leg it stays at its end, at rest.
  // Several copies of a symbol move in formation: each keeps its planned
  // offset from the first copy. Its velocity is the path's; an object
  // standing on the terrain follows the ground, so the vertical component
  // is the terrain's slope along the motion (its z is re-seated on the
  // support by KeepPlacement).
  void Move(const Rule& rule, const PlannedObject& o, int64_t k, ObjectChange* c) const {
    const PlannedObject* first = &o;
    for (const PlannedObject& p : plan_->objects)
      if (p.symbol == o.symbol) {
        first = &p;
        break;
      }
    double t = static_cast<double>(k - rule.begin) / fps_;
    FlightSample at;
    bool moving = false;
    for (const Rule::Leg& leg : rule.legs) {
      const Flight& flight = *leg.flight;
      const double lap = flight.length / flight.speed;
      if (t < lap * static_cast<double>(leg.repetitions)) {
        at = flight.At((t - std::floor(t / lap) * lap) * flight.speed);
        moving = true;
        break;
      }
      t -= lap * static_cast<double>(leg.repetitions);
      at = flight.At(flight.length);
    }
    c->position = at.centre + (o.position - first->position);
    Eigen::Vector3d v = moving ? at.velocity : Eigen::Vector3d::Zero();
    if (o.support == PlannedObject::Support::kTerrain) {
      const double e = 1e-3;  // central difference of the terrain height
      const Eigen::Vector3d& p = *c->position;
      const double dx = (TerrainHeight(plan_->terrain, p.x() + e, p.y()) -
                         TerrainHeight(plan_->terrain, p.x() - e, p.y())) /
                        (2 * e);
      const double dy = (TerrainHeight(plan_->terrain, p.x(), p.y() + e) -
                         TerrainHeight(plan_->terrain, p.x(), p.y() - e)) /
                        (2 * e);
      v.z() = dx * v.x() + dy * v.y();
    } else if (o.support == PlannedObject::Support::kTop) {
      v.z() = 0;
    }
    c->velocity = v;
    // Heading: the yaw of travel on top of the object's rotation (the
    // block's, else the planned one).
    if (rule.heading && at.tangent.head<2>().norm() > 1e-12) {
      const double yaw = std::atan2(at.tangent.y(), at.tangent.x());
      c->world_from_object = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                             (c->world_from_object ? *c->world_from_object : o.world_from_object);
    }
  }

  // A re-scatter (`rescatter:true`): Algorithm 1 again for the object, in
  // the space its LSCENE constraints left (recorded when it was placed),
  // against the objects as they are on this frame (their changes so far);
  // its overlap policy holds: after `retries` overlapping draws it is hidden
  // on this frame (on_overlap delete or hide) or the plan fails (move).
  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void Rescatter(const Rule& rule,
                 const PlannedObject& o,
                 const PlannedFrame& f,
                 Rng& rng,
                 ObjectChange* c) const {
    struct State {
      const PlannedObject* planned;
      Eigen::Vector3d position, extent;
      Eigen::Matrix3d world_from_object;
      bool visible;
    };
    std::map<std::string, State> states;
    for (const PlannedObject& p : plan_->objects)
      states[p.name] = {&p, p.position, p.extent, p.world_from_object, p.visible};
    for (const ObjectChange& change : f.changes) {
      State& s = states.at(change.object);
      if (change.position) s.position = *change.position;
      if (change.extent) s.extent = *change.extent;
      if (change.world_from_object) s.world_from_object = *change.world_from_object;
      if (change.visible) s.visible = *change.visible;
    }
    State& me = states.at(o.name);
    if (c->extent) me.extent = *c->extent;
    if (c->world_from_object) me.world_from_object = *c->world_from_object;
    if (c->visible) me.visible = *c->visible;
    // Its LSCENE relations hold on the new place too (the references where
    // the scene put them): a draw outside NEAR / BEHIND / IN FRONT OF or with
    // a blocked VISIBLE FROM line of sight is drawn again; FACING turns it to
    // its point from the new place (drawn with the half-width no turn exceeds).
    const Eigen::Matrix3d unturned = me.world_from_object;
    Eigen::Vector3d half = me.world_from_object.cwiseAbs() * (0.5 * me.extent);
    if (o.facing) half.head<2>().setConstant(HorizontalRadius(unturned, me.extent));
    const bool on = o.support != PlannedObject::Support::kNone;
    const std::string* broken = nullptr;  // the relation the last draw broke
    for (int attempt = 0;; ++attempt) {
      Eigen::Vector3d p;
      for (int i = 0; i < 3; ++i) {
        if (i == 2 && on) continue;
        const double lo = o.placement_lo[i] + half[i], hi = o.placement_hi[i] - half[i];
        p[i] = lo <= hi ? rng.Uniform(lo, hi) : 0.5 * (o.placement_lo[i] + o.placement_hi[i]);
      }
      if (o.support == PlannedObject::Support::kTerrain)
        p.z() = TerrainHeight(plan_->terrain, p.x(), p.y()) + half.z();
      else if (o.support == PlannedObject::Support::kTop)
        p.z() = o.support_top + half.z();
      c->position = p;
      if (o.facing) {
        me.world_from_object = FacingRotation(unturned, p, *o.facing);
        c->world_from_object = me.world_from_object;
      }
      broken = nullptr;
      for (const auto& [relation, what] : o.relations)
        if (!RelationHolds(relation, p)) broken = &what;
      for (const PlannedObject::Sight& sight : o.sights)
        for (const auto& [name, t] : states)
          if (name != o.name && name != sight.viewer && t.visible &&
              SegmentCrossesBox({t.position, 0.5 * t.extent, t.world_from_object}, sight.eye, p))
            broken = &sight.what;
      if (broken) {
        if (attempt >= o.retries) break;
        continue;
      }
      if (o.overlap_allowed || !me.visible) return;
      bool collides = false;
      for (const auto& [name, t] : states) {
        if (name == o.name || !t.visible) continue;
        if (std::find(o.supports.begin(), o.supports.end(), t.planned->symbol) != o.supports.end())
          continue;
        // LSCENE separation: the larger gap of the two is kept free.
        const double gap = std::max(o.separation, t.planned->separation);
        const OrientedBox mine{
            p, 0.5 * me.extent + Eigen::Vector3d::Constant(gap), me.world_from_object};
        if (mine.Intersects({t.position, 0.5 * t.extent, t.world_from_object})) {
          collides = true;
          break;
        }
      }
      if (!collides) return;
      if (attempt >= o.retries) break;
    }
    if (o.on_overlap == "delete" || o.on_overlap == "hide") {
      c->visible = false;  // a frame cannot delete it: it is hidden there
      return;
    }
    if (broken)
      rule.block.Fail("frame " + std::to_string(f.index) + ": cannot re-scatter " + o.name +
                      " satisfying " + *broken + " after " + std::to_string(o.retries) +
                      " retries; widen the relation or its space, or raise retries");
    rule.block.Fail("frame " + std::to_string(f.index) + ": cannot re-scatter " + o.name +
                    " without overlap after " + std::to_string(o.retries) +
                    " retries; lower the count, enlarge its space, or allow "
                    "overlap in the scene (overlap:true or on_overlap:delete)");
  }

  // A camera must be where a drone can be: at least the clearance above the
  // terrain under it and outside every rendered object grown by it.
  // A violation is a plan error naming the path instance, the pose and the
  // terrain height there; `clearance:off` opts out.
  void CheckClearance(const Segment& seg,
                      int64_t k,
                      const PlannedFrame& f,
                      const Rigid3d& cam_from_world) const {
    if (!clearance_) return;
    const Eigen::Vector3d eye = CameraCenterInWorld(cam_from_world);
    const std::string who = seg.path->symbol + "(" + std::to_string(seg.repetition) + ") pose " +
                            std::to_string(k - seg.first) + " (frame " + std::to_string(f.index) +
                            (f.rig_camera ? ", rig camera " + *f.rig_camera : std::string()) + ")";
    const std::string fix = "; raise the path, or set camera settings clearance:" +
                            std::string("N (metres) or clearance:off");
    if (plan_->terrain.present) {
      const double ground = TerrainHeight(plan_->terrain, eye.x(), eye.y());
      if (eye.z() < ground + *clearance_)
        seg.path->body.Fail(who + ": the camera at (" + FormatNumber(eye.x()) + ", " +
                            FormatNumber(eye.y()) + ", " + FormatNumber(eye.z()) + ") is " +
                            FormatNumber(eye.z() - ground) + " m above the terrain (height " +
                            FormatNumber(ground) + " m there), under the clearance of " +
                            FormatNumber(*clearance_) + " m" + fix);
    }
    for (const PlannedObject& o : plan_->objects) {
      if (!o.visible) continue;
      const OrientedBox grown{
          o.position, 0.5 * o.extent + Eigen::Vector3d::Constant(*clearance_), o.world_from_object};
      const Eigen::Vector3d local = grown.world_from_box.transpose() * (eye - grown.center);
      if ((local.cwiseAbs() - grown.half_extents).maxCoeff() < 0)
        seg.path->body.Fail(who + ": the camera is within " + FormatNumber(*clearance_) +
                            " m of object " + o.name + fix);
    }
  }

  // A change of size, rotation or offset re-applies the object's LSCENE
  // placement: an object ON a support keeps its base on the support's top (on
  // the terrain: the height under its new centre, as Algorithm 1 places it),
  // and an object that may not overlap must not overlap another after the
  // change. The re-seated position is appended as a final change of the
  // frame; an overlap is a plan error at the change that caused it.
  struct State {
    const PlannedObject* planned = nullptr;
    Eigen::Vector3d position, extent;
    Eigen::Matrix3d world_from_object;
    bool visible = true, moved = false;
    const Rule* rule = nullptr;  // the last geometry change, for errors
  };

  // Objects standing ON (or placed IN) a moved object ride with it
  // (docs/languages.md, "Scene changes keep the placement"): the carrier's
  // rigid displacement since the plan (translation and turn; its top's
  // rise when it grew) is applied to each rider that has no geometry change
  // of its own, in placement order so that a stack moves as one. The rider
  // is the copy whose planned footprint holds the rider's planned centre.
  // Each rider's new pose is appended as a change of the frame, with the
  // carrier's velocity. Returns the riders moved.
  std::set<std::string> CarryRiders(PlannedFrame* f, std::map<std::string, State>* states) const {
    std::set<std::string> carried;
    std::map<std::string, Eigen::Vector3d> velocities;
    for (const ObjectChange& c : f->changes)
      if (c.velocity) velocities[c.object] = *c.velocity;
    for (const PlannedObject& rider : plan_->objects) {
      State& r = states->at(rider.name);
      if (r.moved || rider.supports.empty()) continue;
      for (const PlannedObject& carrier : plan_->objects) {
        if (&carrier == &rider ||
            std::find(rider.supports.begin(), rider.supports.end(), carrier.symbol) ==
                rider.supports.end())
          continue;
        const Eigen::Vector3d half = carrier.world_from_object.cwiseAbs() * (0.5 * carrier.extent);
        const Eigen::Vector3d d = (rider.position - carrier.position).cwiseAbs();
        if (d.x() > half.x() + 1e-9 || d.y() > half.y() + 1e-9) continue;  // not this copy
        const State& c = states->at(carrier.name);
        if (!c.moved) break;
        const Eigen::Matrix3d turn = c.world_from_object * carrier.world_from_object.transpose();
        const double rise = (c.world_from_object.cwiseAbs() * (0.5 * c.extent)).z() - half.z();
        r.position =
            c.position + turn * (rider.position - carrier.position) + Eigen::Vector3d(0, 0, rise);
        r.world_from_object = turn * rider.world_from_object;
        r.moved = true;
        r.rule = c.rule;
        carried.insert(rider.name);
        ObjectChange ride;
        ride.object = rider.name;
        ride.position = r.position;
        if (!turn.isIdentity(1e-12)) ride.world_from_object = r.world_from_object;
        const auto v = velocities.find(carrier.name);
        if (v != velocities.end()) {
          ride.velocity = v->second;
          velocities[rider.name] = v->second;
        }
        f->changes.push_back(ride);
        break;
      }
    }
    return carried;
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void KeepPlacement(const std::vector<const Rule*>& change_rules, PlannedFrame* f) const {
    std::map<std::string, State> states;
    for (const PlannedObject& o : plan_->objects)
      states[o.name] = {&o, o.position, o.extent, o.world_from_object, o.visible, false, nullptr};
    for (size_t i = 0; i < f->changes.size(); ++i) {
      const ObjectChange& c = f->changes[i];
      State& s = states.at(c.object);
      if (c.visible) s.visible = *c.visible;
      if (!c.position && !c.extent && !c.world_from_object) continue;
      if (c.position) s.position = *c.position;
      if (c.extent) s.extent = *c.extent;
      if (c.world_from_object) s.world_from_object = *c.world_from_object;
      s.moved = true;
      s.rule = change_rules[i];
    }
    for (auto& [name, s] : states) {
      if (!s.moved) continue;
      const PlannedObject& o = *s.planned;
      const double half_z = (s.world_from_object.cwiseAbs() * (0.5 * s.extent)).z();
      // An offset's z lifts the object off its support on purpose.
      double lift = 0;
      for (const auto& [key, v] : s.rule->block.Members())
        if (CanonicalKey(key) == "offset") lift = s.position.z() - o.position.z();
      if (o.support == PlannedObject::Support::kTerrain) {
        s.position.z() =
            TerrainHeight(plan_->terrain, s.position.x(), s.position.y()) + half_z + lift;
      } else if (o.support == PlannedObject::Support::kTop) {
        s.position.z() = o.support_top + half_z + lift;
      } else {
        continue;  // no support: the change is taken as written
      }
      ObjectChange seat;
      seat.object = name;
      seat.position = s.position;
      f->changes.push_back(seat);
    }
    // Riders follow their carriers' final (re-seated) poses.
    CarryRiders(f, &states);
    for (const auto& [name, s] : states) {
      if (!s.moved || !s.visible || s.planned->overlap_allowed) continue;
      const OrientedBox mine{s.position, 0.5 * s.extent, s.world_from_object};
      for (const auto& [other_name, t] : states) {
        if (other_name == name || !t.visible) continue;
        const auto& supports = s.planned->supports;
        if (std::find(supports.begin(), supports.end(), t.planned->symbol) != supports.end())
          continue;
        // Nor with what stands on it (its riders touch its top).
        const auto& theirs_on = t.planned->supports;
        if (std::find(theirs_on.begin(), theirs_on.end(), s.planned->symbol) != theirs_on.end())
          continue;
        const OrientedBox theirs{t.position, 0.5 * t.extent, t.world_from_object};
        if (mine.Intersects(theirs))
          s.rule->block.Fail("frame " + std::to_string(f->index) + ": this change makes " + name +
                             " overlap " + other_name +
                             ", which its LSCENE placement forbids; change less, or allow "
                             "overlap in the scene (overlap:true or on_overlap:allow)");
      }
    }
  }

 public:
  std::set<std::string> scene_symbols_;
  std::map<std::string, std::string> environment_symbols_;  // symbol -> kind
  std::string first_target_;
  const Program* scene_ = nullptr;
  std::optional<gen::AssetLibrary> library_;  // the scene's asset_library, if any
  bool library_loaded_ = false;
  TargetLabels labels_;
  std::set<uint32_t> swapped_in_;  // class ids class changes may draw

 private:
  const Program& cap_;
  uint64_t seed_;
  Plan* plan_;
  const Definition* camera_ = nullptr;
  PinholeCamera camera_model_;
  double fps_ = 10;
  std::optional<double> clearance_ = kDefaultClearanceM;
  std::map<uint64_t, Flight> flights_;                            // by path instance (segment)
  std::map<std::pair<uint64_t, size_t>, Flight> object_flights_;  // by (rule, leg)
  bool heights_agl_ = false;  // waypoint and point z above the terrain
  std::vector<Segment> segments_;
  std::vector<Rule> rules_;
};

}  // namespace

// Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
TargetLabels ReadTargets(const Program& capture, const Program& scene) {
  TargetLabels labels;
  for (const Definition& d : capture.definitions) {
    if (d.kind != "camera") continue;
    const Node t = d.body.Find("targets");
    if (!t) continue;
    std::vector<Node> items;
    if (t->is_array()) {
      for (size_t i = 0; i < t->size(); ++i) items.push_back(t.Item(i));
    } else if (t->is_object()) {
      for (const auto& [key, value] : t.Members())
        items.push_back(Node{t.src, nullptr, value.pointer});
    } else {
      t.Fail("targets are a list [O1:5, ...]");
    }
    for (size_t i = 0; i < items.size(); ++i) {
      std::string symbol;
      int64_t label = 0;
      if (items[i].value) {
        std::tie(symbol, label) = RefWithNumber(items[i]);
      } else {
        const auto [key, value] = t.Members()[i];
        symbol = key;
        label = static_cast<int64_t>(ReadNumber(value));
      }
      const Node& where = items[i].value ? items[i] : t;
      const Definition* def = scene.Find(symbol);
      if (!def || def->kind != "object") {
        std::vector<std::string> names;
        for (const Definition& s : scene.definitions)
          if (s.kind == "object") names.push_back(s.symbol);
        where.Fail("target '" + symbol + "' is not an object of the scene" +
                   DidYouMean(symbol, names));
      }
      // -1: listed without a label ("O2"); its class comes from the scene.
      if (label == 0 || label > 0xFFFFFFFFll) where.Fail("a label id must be in [1, 4294967295]");
      labels[symbol] = static_cast<uint32_t>(label < 0 ? 0 : label);
    }
  }
  return labels;
}

void EvaluateCapture(const Program& capture,
                     const Program& scene,
                     uint64_t seed,
                     int64_t begin,
                     int64_t end,
                     Plan* plan,
                     const FrameEstimatorFactory& estimator) {
  CaptureEvaluator evaluator(capture, seed, plan);
  evaluator.requirements_ = ReadRequirements(capture, scene);
  evaluator.estimator_factory_ = estimator;
  evaluator.scene_ = &scene;
  evaluator.labels_ = ReadTargets(capture, scene);
  for (const Definition& d : scene.definitions)
    if (d.kind == "object")
      evaluator.scene_symbols_.insert(d.symbol);
    else if (IsEnvironmentKind(d.kind))
      evaluator.environment_symbols_[d.symbol] = d.kind;
  for (const Definition& d : capture.definitions)
    if (d.kind == "camera")
      if (const Node t = d.body.Find("targets"); t && t->is_array() && !t->empty())
        if (t->at(0).is_string())
          evaluator.first_target_ =
              t->at(0).get<std::string>().substr(0, t->at(0).get<std::string>().find(':'));
  evaluator.Run(begin, end);
}

void DefaultCapture(int64_t begin, int64_t end, Plan* plan) {
  DropHelperClasses({}, plan);
  if (end < 0 || end > 1) end = 1;
  if (begin >= end) return;
  Eigen::Vector2d center(0, 0);
  double across = 10, ground = 0;
  if (plan->terrain.present) {
    across = std::max(across, plan->terrain.size.maxCoeff());
    ground = std::abs(plan->terrain.perlin_amplitude);
  } else if (!plan->objects.empty()) {
    Eigen::Vector3d lo = plan->objects[0].position, hi = lo;
    for (const PlannedObject& o : plan->objects) {
      lo = lo.cwiseMin(o.position - 0.5 * o.extent);
      hi = hi.cwiseMax(o.position + 0.5 * o.extent);
    }
    center = 0.5 * (lo + hi).head<2>();
    across = std::max(across, (hi - lo).head<2>().maxCoeff());
    ground = hi.z();
  }
  PlannedFrame f;
  f.index = 0;
  f.sequence = "default(1)";
  f.shot = 0;
  f.camera = PinholeCamera::FromHorizontalFov(1024, 1024, 60);
  const double altitude = ground + 0.5 * across / std::tan(30.0 * M_PI / 180.0);
  f.cam_from_world = CamFromEnu({center.x(), center.y(), altitude}, Attitude{0, -90, 0});
  plan->frames.push_back(f);
}

}  // namespace lsds
