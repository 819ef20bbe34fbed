#include "generator/lang/scene.h"

#include <optional>
#include <string>
#include <vector>

#include "generator/lang/asset_choice.h"
#include "generator/lang/environment.h"
#include "generator/lang/scene/blueprints.h"
#include "generator/lang/scene/class_catalog.h"
#include "generator/lang/scene/class_table.h"
#include "generator/lang/scene/ground.h"
#include "generator/lang/scene/placed_objects.h"
#include "generator/lang/scene/position.h"
#include "generator/lang/scene/scene_check.h"
#include "generator/lang/vocabulary.h"
#include "generator/scene/object_library.h"

namespace lsds {

const std::map<std::string, Eigen::Vector3d>& BuiltinClasses() {
  // Read from the object library's one table (generator/scene/object_library.h).
  static const std::map<std::string, Eigen::Vector3d> classes = [] {
    std::map<std::string, Eigen::Vector3d> out;
    for (const gen::BuiltinClass& c : gen::BuiltinClassTable())
      out.emplace(c.name, c.default_extent);
    return out;
  }();
  return classes;
}

namespace {

// Evaluates a checked scene in file order: the environment and georeference, the terrain, then
// each object's copies (their class and size drawn, their keys applied in the order written,
// Algorithm 1 for the position).
class SceneEvaluator {
 public:
  SceneEvaluator(const Program& scene, uint64_t seed, const TargetLabels& targets, Plan* plan)
      : scene_(scene),
        seed_(seed),
        targets_(targets),
        plan_(plan),
        assets_(scene),
        rng_(Rng::For(seed, StreamTag::kWorld, 0)) {}

  void Run() {
    symbols_ = CheckScene(scene_, &assets_);
    labelled_ = AssignClassIds(scene_, assets_, targets_, plan_);
    for (const Definition& def : scene_.definitions) Evaluate(def);
    PlaceSunByClock();
    uint32_t instance = 1;
    if (plan_->terrain.present) plan_->terrain.instance_id = instance++;
    for (const Placed& p : placed_.all()) {
      plan_->objects.push_back(p.object);
      plan_->objects.back().instance_id = instance++;
    }
  }

 private:
  void Evaluate(const Definition& def) {
    if (def.kind == "skybox" || def.kind == "light" || def.kind == "atmosphere" ||
        def.kind == "skylight") {
      PlannedEnvironment environment = EnvironmentOf(*plan_);
      ApplyEnvironment(def.kind, def.body, rng_, &environment);
      for (std::string& w : ImplausibleLight(def.kind, def.body, environment))
        plan_->warnings.push_back(std::move(w));
      SetEnvironment(environment, plan_);
    } else if (def.kind == "georeference") {
      plan_->geo = EvaluateGeoreference(def.body, rng_);
    } else if (def.kind == "terrain") {
      EvaluateTerrain(def.body, seed_, rng_, plan_);
    } else if (def.kind == "object") {
      EvaluateObject(def);
    }
  }

  // A sun by date and time needs a place; its position at capture time 0 is the plan's own (each
  // frame gets its own in the capture).
  void PlaceSunByClock() {
    if (!plan_->sun.clock_utc_s) return;
    if (!plan_->geo)
      for (const Definition& def : scene_.definitions)
        if (def.kind == "light")
          for (const char* key : {"date", "time"})
            if (const Node n = def.body.Find(key))
              n.Fail(
                  "a sun given by date and time needs a place: add a "
                  "georeference{latitude, longitude, altitude}");
    if (plan_->geo) PlaceSun(*plan_->geo, 0.0, &plan_->sun);
  }

  int64_t CountOf(const Definition& def) {
    if (const Node n = def.body.Find("count")) return SampleCount(n, rng_);
    auto it = symbols_.start_counts.find(def.symbol);
    if (it != symbols_.start_counts.end() && it->second) return SampleCount(it->second, rng_);
    if (symbols_.many_without_count.count(def.symbol)) return rng_.UniformInt(5, 15);
    return 1;
  }

  static OverlapRules OverlapRulesOf(const Node& b, Rng& rng) {
    OverlapRules rules;
    if (const Node n = b.Find("overlap")) rules.overlap = SampleBool(n, rng);
    if (const Node n = b.Find("onoverlap")) rules.on_overlap = ReadString(n);
    if (const Node n = b.Find("retries"))
      rules.retries = static_cast<int>(ReadInRange(n, KindVocabulary("object").Key("retries")));
    return rules;
  }

  void EvaluateObject(const Definition& def) {
    const int64_t count = CountOf(def);
    const OverlapRules rules = OverlapRulesOf(def.body, rng_);
    // A placement requirement: a free margin around the object (metres).
    double separation = 0;
    if (const Node n = def.body.Find("separation")) {
      separation = ReadInRange(n, KindVocabulary("object").Key("separation"));
      if (rules.overlap) n.Fail("separation keeps objects apart; it needs overlap:false");
    }
    int64_t copy_number = 0;
    for (int64_t copy = 0; copy < count; ++copy) {
      Placed p;
      p.object.symbol = def.symbol;
      p.object.separation = separation;
      const std::optional<DrawnBlueprint> group = DrawClass(def, &p.object);
      DrawLooks(def, &p.object);
      if (!ApplyGeometry(def, copy, count, rules, &p)) continue;
      p.object.name = def.symbol + "#" + std::to_string(++copy_number);
      if (group) {
        AddGroup(def, *group, &p);
        continue;
      }
      placed_.Add(p);
    }
  }

  // A placed blueprint group: its box stays as an invisible helper (placed like a zone, not
  // rendered), its members are the objects, each with its class's id.
  void AddGroup(const Definition& def, const DrawnBlueprint& group, Placed* p) {
    std::vector<PlannedObject> members = PlaceMembers(group, *p, plan_->terrain);
    p->object.visible = false;
    p->object.target = false;
    placed_.Add(*p);
    for (size_t i = 0; i < members.size(); ++i) {  // in the blueprint's order
      Placed m;
      m.object = std::move(members[i]);
      m.object.class_id = ClassIdOf(*plan_, labelled_, def.symbol, group.members[i].drawn.name);
      m.aabb = AabbOf(m.object.position, m.object.world_from_object, m.object.extent);
      m.support = p->support;
      m.has_support = p->has_support;
      placed_.Add(m);
    }
  }

  // A blueprint drawn is the group's members; the object is then the group's box.
  std::optional<DrawnBlueprint> DrawClass(const Definition& def, PlannedObject* o) {
    const Node cls = def.body.Find("class");
    const std::string chosen = IsTagSelection(cls) ? "tags" : SampleString(cls, rng_);
    if (const Definition* blueprint = assets_.Blueprint(chosen)) {
      DrawnBlueprint group = DrawBlueprint(*blueprint, &assets_, rng_);
      o->class_name = "cube";  // the group's box: an invisible helper once placed
      o->class_id = 0;
      o->extent = group.extent;
      return group;
    }
    const std::vector<const gen::LibraryAsset*> selected =
        SelectAssets(assets_.Library(), cls, chosen);
    const std::string what = "object " + def.symbol;
    if (!selected.empty()) {
      const gen::LibraryAsset& a = *selected[static_cast<size_t>(
          rng_.UniformInt(0, static_cast<int64_t>(selected.size()) - 1))];
      o->class_name = a.file;
      o->class_id = ClassIdOf(*plan_, labelled_, def.symbol, AssetClassName(a));
      o->extent = assets_.NaturalExtent(a.file, a.DeclaredMetresPerUnit(), cls, what);
    } else {
      const SceneClass drawn = assets_.Resolve(cls, chosen);
      o->class_name = drawn.asset;
      o->class_id = ClassIdOf(*plan_, labelled_, def.symbol, drawn.name);
      o->extent = assets_.NaturalExtent(drawn.asset,
                                        MetresPerUnit(def),
                                        cls,
                                        what,
                                        rng_.KeyHere(ClassCatalog::kMemberKeyPurpose));
    }
    return std::nullopt;
  }

  // Visibility, material and whether it is a target.
  void DrawLooks(const Definition& def, PlannedObject* o) {
    const Node& b = def.body;
    if (const Node n = FindKey(b, KindVocabulary("object"), "visible"))
      o->visible = SampleBool(n, rng_);
    if (const Node n = b.Find("material")) o->material = SampleString(n, rng_);
    o->target = o->visible && (targets_.empty() || targets_.count(def.symbol) > 0);
    if (const Node n = b.Find("target")) o->target = SampleBool(n, rng_);
  }

  // The geometry keys in the order written: a size given after `position` is applied after the
  // collision test (the paper's trick for gaps or overlaps, section 3.1). False when the copy is
  // deleted.
  bool ApplyGeometry(
      const Definition& def, int64_t copy, int64_t count, const OverlapRules& rules, Placed* p) {
    const PlacementContext context{placed_, symbols_.terrain, plan_->terrain, plan_->geo, rng_};
    PlannedObject& o = p->object;
    bool positioned = false, keep = true;
    for (const auto& [key, n] : def.body.Members()) {
      const std::string k = CanonicalKey(key);
      if (k == "extent") Resize(p, SizeVec(n), positioned);
      if (k == "bound") {
        const std::string ref = ReadString(n);
        Resize(p, placed_.FirstCopy(scene_.Find(ref)->statement, ref).object.extent, positioned);
      }
      if (k == "scale") {
        const Eigen::Vector3d s = SampleScale(n, rng_);
        CheckRange(n, KindVocabulary("object").Key("scale"), s.minCoeff());
        Resize(p, o.extent.cwiseProduct(s), positioned);
      }
      if (k == "rotation") {
        o.world_from_object = RotationFromEulerDeg(SampleVec3(n, rng_));
        if (positioned) Reseat(p);
      }
      if (k == "position") {
        keep = PlaceObject(context, def, n, copy, count, rules, p);
        positioned = true;
      }
    }
    if (!positioned)
      keep = PlaceObject(
          context, def, Node{def.body.src, nullptr, def.body.pointer}, copy, count, rules, p);
    return keep;
  }

  Eigen::Vector3d SizeVec(const Node& n) {
    Eigen::Vector3d e = SampleVec3(n, rng_);
    CheckRange(n, KindVocabulary("object").Key("extent"), e.minCoeff());
    return e;
  }

  // Changes the size; once placed, keeps the base where it is.
  static void Resize(Placed* p, const Eigen::Vector3d& extent, bool positioned) {
    p->object.extent = extent;
    if (positioned) Reseat(p);
  }
  static void Reseat(Placed* p) {
    const double old_base = p->aabb.lo.z();
    p->aabb = AabbOf(p->object.position, p->object.world_from_object, p->object.extent);
    p->object.position.z() += old_base - p->aabb.lo.z();
    p->aabb = AabbOf(p->object.position, p->object.world_from_object, p->object.extent);
  }

  const Program& scene_;
  uint64_t seed_;
  const TargetLabels& targets_;
  Plan* plan_;
  ClassCatalog assets_;
  SceneSymbols symbols_;
  TargetClassIds labelled_;  // the labelled targets' class ids
  Rng rng_;
  PlacedObjects placed_;
};

}  // namespace

void EvaluateScene(const Program& scene, uint64_t seed, const TargetLabels& targets, Plan* plan) {
  SceneEvaluator(scene, seed, targets, plan).Run();
}

void DropHelperClasses(const std::set<std::string>& symbols_made_visible,
                       Plan* plan,
                       const std::set<uint32_t>& extra_shown) {
  std::set<uint32_t> shown = extra_shown;
  if (plan->terrain.present) shown.insert(plan->terrain.class_id);
  for (const PlannedObject& o : plan->objects)
    if (o.visible || symbols_made_visible.count(o.symbol)) shown.insert(o.class_id);
  std::vector<ClassInfo> kept;
  for (const ClassInfo& c : plan->classes)
    if (shown.count(c.id)) kept.push_back(c);
  plan->classes = kept;
  for (PlannedObject& o : plan->objects)
    if (!shown.count(o.class_id)) o.class_id = 0;
}

}  // namespace lsds
