#include "generator/lang/capture.h"

#include <algorithm>
#include <optional>
#include <set>
#include <vector>

#include "generator/lang/capture/camera_paths.h"
#include "generator/lang/capture/camera_setup.h"
#include "generator/lang/capture/change_rules.h"
#include "generator/lang/capture/class_swaps.h"
#include "generator/lang/capture/clearance.h"
#include "generator/lang/capture/keep_placement.h"
#include "generator/lang/capture/object_changes.h"
#include "generator/lang/capture/quota_draws.h"
#include "generator/lang/capture/rescatter.h"
#include "generator/lang/capture/targets.h"
#include "generator/lang/capture/timeline.h"
#include "generator/lang/environment.h"
#include "generator/lang/vocabulary.h"
#include "libs/geometry/attitude.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// The capture's definitions checked: one camera, paths with one generator each, no LSCENE kinds,
// a start rule naming defined symbols. Returns the camera (null when none).
const Definition* CheckCapture(const Program& capture) {
  const Definition* camera = nullptr;
  for (const Definition& d : capture.definitions) {
    if (d.kind == "camera") {
      if (camera)
        d.statement.Fail(
            "one camera per capture; several cameras on one platform are a rig: "
            "camera{rig:{left:{position:[-0.1,0,0]},right:{position:[0.1,0,0]}}}");
      camera = &d;
      lsds::CheckKeys(d.body, KindVocabulary("camera"), "camera " + d.symbol);
    } else if (d.kind == "path") {
      const KindSpec& path = KindVocabulary("path");
      d.body.CheckKeys(path.Spellings(), "path " + d.symbol);
      if (d.body->size() != 1)
        d.body.Fail("a path has exactly one generator: " + Join(path.Spellings(), ", "));
    } else if (IsRequirementKind(d.kind)) {
      CheckRequirementDefinition(d);
    } else if (d.kind != "collection" && d.kind != "scene_change") {
      d.statement.Fail("'" + d.kind + "' belongs in the LSCENE scene file, not in LCAP");
    }
  }
  if (!capture.start_rule) return camera;
  for (size_t i = 0; i < capture.start_rule->size(); ++i) {
    const Node e = capture.start_rule.Item(i);
    if (!e->is_object()) e.Fail("expected ONE(...) or MANY(...)");
    e.CheckKeys({"ONE", "MANY", "count"}, "the start rule");
    const Node sym = e.Child("ONE") ? e.Child("ONE") : e.Child("MANY");
    if (!sym) e.Fail("expected ONE(...) or MANY(...)");
    const std::string name = ReadString(sym);
    if (!capture.Find(name) && !CategoryKinds().count(name)) {
      std::vector<std::string> names;
      for (const Definition& d : capture.definitions) names.push_back(d.symbol);
      sym.Fail("the start rule names undefined symbol '" + name + "'" + DidYouMean(name, names));
    }
  }
  return camera;
}

// What a collection entry may name besides the camera: the scene's objects and environment.
ChangeTargets SceneTargets(const Program& scene) {
  ChangeTargets targets;
  for (const Definition& d : scene.definitions)
    if (d.kind == "object")
      targets.scene_objects.insert(d.symbol);
    else if (IsEnvironmentKind(d.kind))
      targets.environment_symbols[d.symbol] = d.kind;
  return targets;
}

// The LCAP evaluator: composes the units of generator/lang/capture/ into the frames of the plan.
class CaptureEvaluator {
 public:
  CaptureEvaluator(const Program& capture, const Program& scene, uint64_t seed, Plan* plan)
      : capture_(capture),
        seed_(seed),
        plan_(plan),
        targets_(SceneTargets(scene)),
        swaps_(scene, ReadTargets(capture, scene), plan) {}

  // `requirements` were read before the scene was sampled (they steer it).
  void Run(RequirementSet requirements,
           const FrameEstimatorFactory& estimator,
           int64_t begin,
           int64_t end) {
    requirements_ = std::move(requirements);
    setup_ = ReadCameraSetup(CheckCapture(capture_), plan_);
    paths_.emplace(setup_, *plan_, seed_, FirstTarget(capture_), &capture_);
    const auto is_camera_entry = [this](const std::string& key, const Node& value) {
      return IsCameraEntry(key, value);
    };
    timeline_.emplace(capture_, is_camera_entry, [this](const Definition& path, uint64_t segment) {
      return paths_->FrameCount(path, segment);
    });
    rules_ = ReadChangeRules(
        capture_, *timeline_, is_camera_entry, targets_, setup_, &*paths_, seed_, &swaps_, plan_);
    DropHelperClasses(MadeVisible(), plan_, swaps_.swapped_in());
    ResolveQuotaClasses(plan_->classes, &requirements_);
    // Paths give time steps; a rig has one frame per camera per step.
    const int64_t steps = timeline_->steps();
    const int64_t total = steps * RigSize();
    if (end < 0 || end > total) end = total;
    if (requirements_.empty()) {
      for (int64_t k = std::max<int64_t>(0, begin); k < end; ++k)
        plan_->frames.push_back(Frame(k, 0, nullptr));
      return;
    }
    PlanRequiredFrames(estimator, steps, begin, end);
  }

 private:
  // Requirements and quotas (quota_draws.h): redraw each time step until the estimate meets its
  // demand, within the budget. With a rig the unit of redraw is the time step: its cameras move
  // together, and the demand holds in every camera (cameras:all) or in one at least (cameras:any).
  void PlanRequiredFrames(const FrameEstimatorFactory& estimator,
                          int64_t steps,
                          int64_t begin,
                          int64_t end) {
    const int64_t n = RigSize();
    const DemandPlanner demands(requirements_, seed_, steps);
    plan_->requirements = RequirementsProvenance(requirements_, demands);
    if (plan_->rig) plan_->requirements["unit"] = "step";
    QuotaDraws draws(
        requirements_,
        estimator,
        *plan_,
        capture_.definitions.empty() ? Location{} : capture_.definitions.front().statement.Where());
    for (int64_t step = std::max<int64_t>(0, begin) / n; step * n < end; ++step) {
      const auto draw = [&](int attempt, const FrameDemand* demand) {
        std::vector<PlannedFrame> frames;
        for (int64_t c = 0; c < n; ++c) frames.push_back(Frame(step * n + c, attempt, demand));
        return frames;
      };
      for (PlannedFrame& f : draws.Step(step, demands.For(step), draw))
        if (f.index >= begin && f.index < end) plan_->frames.push_back(std::move(f));
    }
  }

  // The symbols a scene change makes visible: their helper classes stay in the class table.
  std::set<std::string> MadeVisible() const {
    std::set<std::string> made_visible;
    for (const Rule& rule : rules_)
      for (const auto& [key, v] : rule.block.Members())
        if (CanonicalKey(key) == "visible" || CanonicalKey(key) == "visibility")
          made_visible.insert(rule.object_symbol);
    return made_visible;
  }

  // The camera's entry in a collection: its symbol, or (the paper writes "C1" for camera "CO")
  // any undefined name whose block moves the camera.
  bool IsCameraEntry(const std::string& key, const Node& value) const {
    if (setup_.camera && key == setup_.camera->symbol) return true;
    if (capture_.Find(key) || HasObject(*plan_, targets_, key)) return false;
    for (const Node& b : Blocks(value))
      if (b->is_object() && b.Find("move")) return true;
    return false;
  }

  int64_t RigSize() const {
    return plan_->rig ? static_cast<int64_t>(plan_->rig->cameras.size()) : 1;
  }

  // Frame k: time step k / n of the paths, seen by rig camera k % n (n = 1 without a rig, so that
  // the step is the frame), draw number `attempt` under `demand` (may be null). Everything drawn
  // is keyed by the step, so the cameras of one step see one world.
  PlannedFrame Frame(int64_t frame_index, int attempt, const FrameDemand* demand) {
    const int64_t n = RigSize();
    const int64_t k = frame_index / n;  // the time step
    const int64_t c = frame_index % n;  // the rig camera
    const Segment& seg = timeline_->At(k);
    const uint64_t segment = static_cast<uint64_t>(&seg - timeline_->segments().data());
    PlannedFrame f;
    f.index = frame_index;
    f.time = static_cast<double>(k) / setup_.fps;
    f.sequence = seg.path->symbol + "(" + std::to_string(seg.repetition) + ")";
    f.shot = paths_->ShotStart(*seg.path, seg.first, k - seg.first) * n + c;
    f.camera = setup_.intrinsics;
    const uint64_t frame_seed = RedrawSeed(seed_, attempt);
    // The scene changes first: a camera that looks at an object aims where it is on this frame.
    // Every draw has its own stream, so the order changes no value.
    ApplyRules(k, frame_seed, demand, &f);
    Rng rng = Rng::For(frame_seed, StreamTag::kFrame, static_cast<uint64_t>(k));
    f.cam_from_world =
        paths_->Pose(*seg.path, k - seg.first, rng, segment, &f.camera_velocity, demand, f.changes);
    if (plan_->rig) SeeFromRigCamera(seg, segment, k, c, &f);
    if (setup_.clearance_m) {
      const auto pose = [&] {
        return seg.path->symbol + "(" + std::to_string(seg.repetition) + ") pose " +
               std::to_string(k - seg.first) + " (frame " + std::to_string(f.index) +
               (f.rig_camera ? ", rig camera " + *f.rig_camera : std::string()) + ")";
      };
      CheckClearance(*plan_,
                     TerrainAt(*plan_, f),
                     *setup_.clearance_m,
                     f.cam_from_world,
                     pose,
                     seg.path->body);
    }
    MoveSun(&f);
    return f;
  }

  // The frame as rig camera `c` sees time step `k` (the path gives the rig's pose).
  void SeeFromRigCamera(
      const Segment& seg, uint64_t segment, int64_t k, int64_t c, PlannedFrame* f) {
    const RigCamera& camera = plan_->rig->cameras[static_cast<size_t>(c)];
    const Rigid3d rig_from_world = f->cam_from_world;
    f->rig_camera = camera.name;
    f->step = k;
    f->camera = camera.intrinsics;
    f->cam_from_world = camera.cam_from_rig * rig_from_world;
    if (f->camera_velocity)
      f->camera_velocity =
          paths_->RigCameraVelocity(*seg.path, segment, k - seg.first, camera.cam_from_rig);
  }

  // The scene changes in effect on time step `k`, then the placement they must keep. An "after"
  // change is drawn once, when it fires; a "during" change on every frame.
  // The environment first (objects on the terrain stand on the frame's ground), then the objects.
  void ApplyRules(int64_t k, uint64_t frame_seed, const FrameDemand* demand, PlannedFrame* f) {
    const Rule* ground_rule = nullptr;  // the last terrain shape change in effect
    for (const Rule& rule : rules_) {
      if (k < rule.when.begin || k >= rule.when.end || rule.environment_kind.empty()) continue;
      Rng change_rng = ChangeRng(rule, k, frame_seed);
      if (!f->environment) f->environment = EnvironmentOf(*plan_);
      ApplyEnvironment(rule.environment_kind, rule.block, change_rng, &*f->environment);
      if (rule.terrain_shape) ground_rule = &rule;
    }
    const PlannedTerrain ground = TerrainAt(*plan_, *f);
    std::vector<const Rule*> change_rules;  // the rule of each change
    for (const Rule& rule : rules_) {
      if (k < rule.when.begin || k >= rule.when.end || !rule.environment_kind.empty()) continue;
      Rng change_rng = ChangeRng(rule, k, frame_seed);
      const bool rescatter =
          rule.block.Find("rescatter") && rule.block.Find("rescatter")->get<bool>();
      for (const PlannedObject& o : plan_->objects)
        if (o.symbol == rule.object_symbol) {
          ObjectChange change = DrawObjectChange(rule, o, change_rng, demand, &swaps_);
          if (!rule.legs.empty()) MoveAlongLegs(rule, o, *plan_, ground, k, setup_.fps, &change);
          if (rescatter) Rescatter(*plan_, rule, o, *f, change_rng, &change);
          f->changes.push_back(change);
          change_rules.push_back(&rule);
        }
    }
    KeepPlacement(*plan_, change_rules, f, ground_rule);
  }

  // The stream of a change on step `k`: an "after" change (and a terrain shape change, which
  // holds for whole shots) is drawn once, when it fires; a "during" change on every frame.
  Rng ChangeRng(const Rule& rule, int64_t k, uint64_t frame_seed) const {
    return rule.when.during && !rule.terrain_shape
               ? Rng::For(frame_seed, StreamTag::kFrame, static_cast<uint64_t>(k), rule.id)
               : Rng::For(
                     seed_, StreamTag::kChange, rule.id, static_cast<uint64_t>(rule.when.begin));
  }

  // A sun given by date and time moves with the frame's time.
  void MoveSun(PlannedFrame* f) const {
    if (!plan_->geo) return;
    PlannedEnvironment environment = EnvironmentAt(*plan_, *f);
    if (!environment.sun.clock_utc_s) return;
    PlaceSun(*plan_->geo, f->time, &environment.sun);
    if (!(environment == EnvironmentOf(*plan_))) f->environment = environment;
  }

  const Program& capture_;
  uint64_t seed_;
  Plan* plan_;
  ChangeTargets targets_;
  ClassSwaps swaps_;
  RequirementSet requirements_;
  CameraSetup setup_;
  std::optional<CameraPaths> paths_;
  std::optional<Timeline> timeline_;
  std::vector<Rule> rules_;
};

}  // namespace

void EvaluateCapture(const Program& capture,
                     const Program& scene,
                     uint64_t seed,
                     int64_t begin,
                     int64_t end,
                     Plan* plan,
                     const FrameEstimatorFactory& estimator) {
  RequirementSet requirements = ReadRequirements(capture, scene);
  CaptureEvaluator evaluator(capture, scene, seed, plan);
  evaluator.Run(std::move(requirements), estimator, begin, end);
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
