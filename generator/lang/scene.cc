#include "generator/lang/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>

#include "generator/lang/asset_choice.h"
#include "generator/lang/environment.h"
#include "generator/lang/placement_grid.h"
#include "generator/lang/vocabulary.h"
#include "generator/plan/relations.h"
#include "generator/plan/terrain_height.h"
#include "generator/scene/mesh_formats.h"
#include "generator/scene/object_library.h"
#include "libs/geometry/oriented_box.h"
#include "libs/util/strings.h"

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

constexpr double kHuge = 1e7;  // the "max sized 3D bounding box" of Algorithm 1
// The placement grid's cell, metres: about the size of the clutter it is for (bushes, rocks,
// vehicles); a building spans a few cells, anything over 64 cells goes on the grid's short list.
constexpr double kPlacementCellM = 4.0;

// The relations with a reference object and an optional distance
// (relations.h): `NEAR:X`, `NEAR:{X:5}`, `BEHIND:{X:[5,20]}`.
bool IsRelationKey(const std::string& canonical) {
  return canonical == "near" || canonical == "behind" || canonical == "infrontof";
}

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(-kHuge);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(kHuge);
  bool EmptyXY() const { return lo.x() > hi.x() || lo.y() > hi.y(); }
  bool Empty() const { return EmptyXY() || lo.z() > hi.z(); }
  void Intersect(const Box& o) {
    lo = lo.cwiseMax(o.lo);
    hi = hi.cwiseMin(o.hi);
  }
  std::string ToString() const {
    auto f = [](double v) {
      if (std::abs(v) >= kHuge) return std::string(v < 0 ? "-inf" : "inf");
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.3g", v);
      return std::string(buf);
    };
    return "[" + f(lo.x()) + "," + f(hi.x()) + "]x[" + f(lo.y()) + "," + f(hi.y()) + "]x[" +
           f(lo.z()) + "," + f(hi.z()) + "]";
  }
};

// Where an object stands: a footprint and either the terrain surface or a flat
// top.
struct Surface {
  Box footprint;  // only x, y used
  bool terrain = false;
  double top = 0;
};

struct Placed {
  PlannedObject object;
  Box aabb;
  Surface support;  // what it stands on (ON), when it has an ON constraint
  bool has_support = false;
};

Box AabbOf(const Eigen::Vector3d& center,
           const Eigen::Matrix3d& rotation,
           const Eigen::Vector3d& extent) {
  const Eigen::Vector3d half = rotation.cwiseAbs() * (0.5 * extent);
  Box b;
  b.lo = center - half;
  b.hi = center + half;
  return b;
}

OrientedBox ObbOf(const PlannedObject& o) {
  OrientedBox b;
  b.center = o.position;
  b.half_extents = 0.5 * o.extent;
  b.world_from_box = o.world_from_object;
  return b;
}

class SceneEvaluator {
 public:
  SceneEvaluator(const Program& scene, uint64_t seed, const TargetLabels& targets, Plan* plan)
      : scene_(scene),
        seed_(seed),
        targets_(targets),
        plan_(plan),
        rng_(Rng::For(seed, StreamTag::kWorld, 0)) {}

  void Run() {
    Check();
    AssignClassIds();
    for (const Definition& def : scene_.definitions) Evaluate(def);
    // A sun by date and time needs a place; its position at capture time 0
    // is the plan's own (each frame gets its own in the capture).
    if (plan_->sun.clock_utc_s) {
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
    uint32_t instance = 1;
    if (plan_->terrain.present) plan_->terrain.instance_id = instance++;
    for (Placed& p : placed_) {
      p.object.instance_id = instance++;
      plan_->objects.push_back(p.object);
    }
  }

 private:
  // --- checking (no sampling) ---
  void Check() {
    std::set<std::string> defined;
    int terrains = 0, georeferences = 0;
    for (const Definition& def : scene_.definitions) {
      const std::string& k = def.kind;
      if (k == "camera" || k == "path" || k == "collection" || k == "scene_change" ||
          k == "require" || k == "quota")
        def.statement.Fail("'" + k + "' belongs in the LCAP capture file, not in LSCENE");
      if (IsEnvironmentKind(k)) CheckKeys(def.body, KindVocabulary(k), def.symbol);
      if (k == "georeference") {
        CheckKeys(def.body, KindVocabulary(k), def.symbol);
        if (++georeferences > 1) def.statement.Fail("only one georeference per scene");
      }
      if (k == "terrain") {
        if (++terrains > 1) def.statement.Fail("only one terrain per scene");
        terrain_symbol_ = def.symbol;
      }
      if (k == "classes") {
        for (const auto& [name, node] : def.body.Members()) {
          const std::string target = ReadString(node);
          if (!BuiltinClasses().count(gen::CanonicalClassName(target)) && !gen::IsMeshPath(target))
            node.Fail("class alias '" + name +
                      "' must name a built-in class or a mesh file, not '" + target + "'" +
                      DidYouMean(target, BuiltinNames()));
          aliases_[name] = target;
        }
      }
      if (k == "asset_library") {
        if (library_) def.statement.Fail("only one asset_library per scene");
        library_ = LoadSceneAssetLibrary(scene_, def);
      }
      if (k == "object") CheckObject(def, defined);
      defined.insert(def.symbol);
    }
    CheckStartRule();
  }

  static std::vector<std::string> BuiltinNames() {
    std::vector<std::string> names;
    for (const auto& [name, extent] : BuiltinClasses()) names.push_back(name);
    return names;
  }

  std::string ResolveClass(const Node& where, const std::string& name) const {
    auto alias = aliases_.find(name);
    if (alias != aliases_.end()) return CanonicalBuiltin(alias->second);
    if (BuiltinClasses().count(CanonicalBuiltin(name))) return CanonicalBuiltin(name);
    if (gen::IsMeshPath(name)) {
      const std::filesystem::path dir = std::filesystem::path(scene_.src->path).parent_path();
      return (dir / name).lexically_normal().generic_string();
    }
    std::vector<std::string> names = BuiltinNames();
    for (const auto& [a, t] : aliases_) names.push_back(a);
    where.Fail("unknown class '" + name + "'" + DidYouMean(name, names) +
               "; use a built-in class (" + Join(BuiltinNames(), ", ") + "), a mesh file (" +
               Join(gen::MeshExtensions(), " ") + ") or declare it in a classes{...} definition");
  }

  // A built-in's other spelling (`rocks`) is the built-in (object_library.h).
  static std::string CanonicalBuiltin(const std::string& name) {
    const std::string canonical = gen::CanonicalClassName(name);
    return canonical.empty() ? name : canonical;
  }

  // The class names a class option labels its objects with: a library
  // selection's asset classes, else ClassNameOf.
  std::vector<std::string> ClassNamesOf(const Node& cls, const std::string& option) const {
    std::vector<std::string> names;
    for (const gen::LibraryAsset* a : SelectAssets(Library(), cls, option))
      names.push_back(AssetClassName(*a));
    if (names.empty()) names.push_back(ClassNameOf(cls, option));
    return names;
  }
  const gen::AssetLibrary* Library() const { return library_ ? &*library_ : nullptr; }

  void CheckReference(const Node& node,
                      const std::set<std::string>& defined,
                      const std::string& symbol,
                      bool objects_only = false) const {
    CheckReferenceName(ReadString(node), node, defined, symbol, objects_only);
  }
  void CheckReferenceName(const std::string& ref,
                          const Node& node,
                          const std::set<std::string>& defined,
                          const std::string& symbol,
                          bool objects_only) const {
    const Definition* def = scene_.Find(ref);
    if (!def) {
      std::vector<std::string> names(defined.begin(), defined.end());
      node.Fail(symbol + " refers to undefined symbol '" + ref + "'" + DidYouMean(ref, names));
    }
    if (ref == symbol) node.Fail(symbol + " refers to itself (a cycle)");
    if (!defined.count(ref))
      node.Fail(symbol + " refers to '" + ref +
                "' before its definition; definitions are evaluated in file order, "
                "so a forward reference or a cycle is not allowed");
    if (def->kind != "object" && (objects_only || def->kind != "terrain"))
      node.Fail("'" + ref + "' is a " + def->kind +
                (objects_only ? ", expected an object" : ", expected an object or the terrain"));
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void CheckObject(const Definition& def, const std::set<std::string>& defined) {
    CheckKeys(def.body, KindVocabulary("object"), "object " + def.symbol);
    const Node cls = def.body.Find("class");
    if (!cls) def.body.Fail("object " + def.symbol + " needs a class (e.g. class:cube)");
    if (!cls->is_string() && !cls->is_object())
      cls.Fail("class must be a name or a choice {name: weight}");
    if (IsTagSelection(cls)) SelectAssets(Library(), cls, "tags");
    for (const auto& [key, child] : cls->is_object() && !IsTagSelection(cls)
                                        ? cls.Members()
                                        : std::vector<std::pair<std::string, Node>>{})
      (void)key, ReadNumber(child);
    for (const std::string& option : StringOptions(cls)) {
      if (!SelectAssets(Library(), cls, option).empty()) continue;  // a library selection
      if (cls->is_object()) {
        try {
          ResolveClass(cls.Child(option), option);
        } catch (const Error& e) {  // point at the option's name, not its weight
          throw Error(e.message(), cls.src->WhereKey(cls.Child(option).pointer));
        }
      } else {
        ResolveClass(cls, option);
      }
    }
    if (const Node pos = def.body.Find("position")) {
      CheckKeys(pos, KindVocabulary("position"), "position of " + def.symbol);
      for (const auto& [key, c] : pos.Members()) {
        const std::string k = CanonicalKey(key);
        if (k == "within") continue;
        if ((k == "around" || IsRelationKey(k)) && c->is_object()) {
          for (const auto& [ref, margin] : c.Members())
            CheckReferenceName(ref, margin, defined, def.symbol, true);
          continue;
        }
        if (k == "visiblefrom" && c->is_array()) {  // an eye point [x, y, z]
          if (c->size() != 3) c.Fail("VISIBLE FROM takes an object or a point [x, y, z]");
          for (size_t i = 0; i < 3; ++i) (void)ReadNumber(c.Item(i));
          continue;
        }
        if (k == "facing" && c->is_array()) {  // a point [x, y] or [x, y, z]
          if (c->size() != 2 && c->size() != 3)
            c.Fail("FACING takes an object or a point [x, y] or [x, y, z]");
          for (size_t i = 0; i < c->size(); ++i) (void)ReadNumber(c.Item(i));
          continue;
        }
        CheckReference(c,
                       defined,
                       def.symbol,
                       k == "around" || k == "facing" || k == "visiblefrom" || IsRelationKey(k));
      }
    }
    if (const Node bound = def.body.Find("bound")) CheckReference(bound, defined, def.symbol, true);
    if (const Node policy = def.body.Find("onoverlap")) {
      const std::string p = ReadString(policy);
      if (p != "move" && p != "delete" && p != "hide" && p != "allow")
        policy.Fail("on_overlap must be move, delete, hide or allow" +
                    DidYouMean(p, {"move", "delete", "hide", "allow"}));
    }
  }

  void CheckStartRule() {
    if (!scene_.start_rule) return;
    for (size_t i = 0; i < scene_.start_rule->size(); ++i) {
      const Node entry = scene_.start_rule.Item(i);
      if (!entry->is_object()) entry.Fail("expected ONE(...) or MANY(...)");
      entry.CheckKeys({"ONE", "MANY", "count"}, "the start rule");
      const Node one = entry.Child("ONE"), many = entry.Child("MANY");
      if (bool(one) == bool(many))
        entry.Fail("each start rule entry is exactly one of ONE or MANY");
      const Node sym = one ? one : many;
      const std::string name = ReadString(sym);
      std::vector<const Definition*> defs;
      if (const Definition* d = scene_.Find(name)) {
        defs.push_back(d);
      } else if (CategoryKinds().count(name)) {
        for (const Definition& d : scene_.definitions)
          if (d.kind == CategoryKinds().at(name)) defs.push_back(&d);
      } else {
        std::vector<std::string> names;
        for (const Definition& d : scene_.definitions) names.push_back(d.symbol);
        sym.Fail("the start rule names undefined symbol '" + name + "'" + DidYouMean(name, names));
      }
      for (const Definition* d : defs) {
        if (many && d->kind != "object")
          sym.Fail("MANY applies to objects only; '" + d->symbol + "' is a " + d->kind);
        if (d->kind == "object") count_nodes_[d->symbol] = many ? entry.Child("count") : Node{};
        if (d->kind == "object" && many && !entry.Child("count")) many_default_.insert(d->symbol);
      }
    }
  }

  // --- class ids: terrain first, then class options in order of first
  // appearance in the file ---
  void AssignClassIds() {
    std::set<uint32_t> reserved;
    for (const auto& [symbol, label] : targets_)
      if (label != 0) reserved.insert(label);
    uint32_t next = 1;
    auto add = [&](const std::string& name) {
      for (const ClassInfo& c : plan_->classes)
        if (c.name == name) return;
      while (reserved.count(next)) ++next;
      plan_->classes.push_back({next++, name});
    };
    for (const Definition& def : scene_.definitions) {
      if (def.kind == "terrain") add("terrain");
      if (def.kind != "object" || LabelOf(def.symbol) != 0) continue;
      const Node cls = def.body.Find("class");
      for (const std::string& option : StringOptions(cls))
        for (const std::string& name : ClassNamesOf(cls, option)) add(name);
    }
    // A labelled target's class is named after what it draws: the class name
    // of its options (docs/languages.md, "Class names"), joined by "|" when
    // the symbol draws several.
    for (const auto& [symbol, label] : targets_) {
      const Definition* def = scene_.Find(symbol);
      if (!def || label == 0) continue;
      const Node cls = def->body.Find("class");
      std::vector<std::string> names;
      for (const std::string& option : StringOptions(cls))
        for (const std::string& name : ClassNamesOf(cls, option))
          if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      std::string name = Join(names, "|");
      // Two labels may not share a name, nor a label a name of the table.
      for (const ClassInfo& c : plan_->classes)
        if (c.name == name) name += "#" + std::to_string(label);
      plan_->classes.push_back({label, name});
    }
    std::sort(plan_->classes.begin(),
              plan_->classes.end(),
              [](const ClassInfo& a, const ClassInfo& b) { return a.id < b.id; });
  }

  // A mesh keeps its native size: its bounds in the file's unit (`unit`,
  // metres by default, as glTF's specification says), in metres.
  Eigen::Vector3d MeshExtent(const Definition& def,
                             const std::string& path,
                             double metres_per_unit) {
    auto cached = mesh_extents_.find(path);
    if (cached == mesh_extents_.end()) {
      Eigen::Vector3d extent;
      try {
        extent = gen::MeshFileExtent(path, "object " + def.symbol);
      } catch (const Error& e) {
        def.body.Find("class").Fail(e.message() + " (" + path + ")");
      }
      // A flat mesh (a plane) still needs a box: 1 mm thick.
      extent = extent.cwiseMax(Eigen::Vector3d::Constant(1e-3));
      cached = mesh_extents_.emplace(path, extent).first;
    }
    return cached->second * metres_per_unit;
  }
  static double MetresPerUnit(const Definition& def) {
    double metres_per_unit = 1.0;
    if (const Node n = def.body.Find("unit")) {
      static const std::map<std::string, double> kUnits = {
          {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}, {"ft", 0.3048}};
      const std::string unit = ReadString(n);
      const auto it = kUnits.find(unit);
      if (it == kUnits.end()) n.Fail("unit must be one of m, cm, mm, in, ft, not '" + unit + "'");
      metres_per_unit = it->second;
    }
    return metres_per_unit;
  }

  // The class name of a class option (docs/languages.md, "Class names"): a
  // classes{} alias keeps its own name (the user's class, e.g. `A`), a
  // built-in is its name, a mesh its resolved path.
  std::string ClassNameOf(const Node& where, const std::string& option) const {
    if (aliases_.count(option)) return option;
    return ResolveClass(where, option);
  }

  uint32_t LabelOf(const std::string& symbol) const {
    auto t = targets_.find(symbol);
    return t == targets_.end() ? 0 : t->second;
  }
  uint32_t ClassIdOf(const std::string& symbol,
                     const std::string& class_name) const {  // by class name
    if (const uint32_t label = LabelOf(symbol)) return label;
    for (const ClassInfo& c : plan_->classes)
      if (c.name == class_name) return c.id;
    return 0;
  }

  // --- evaluation ---
  void Evaluate(const Definition& def) {
    const Node& b = def.body;
    if (def.kind == "skybox" || def.kind == "light" || def.kind == "atmosphere" ||
        def.kind == "skylight") {
      PlannedEnvironment environment = EnvironmentOf(*plan_);
      ApplyEnvironment(def.kind, b, rng_, &environment);
      SetEnvironment(environment, plan_);
    } else if (def.kind == "georeference") {
      GeoOrigin geo;
      const KindSpec& vocabulary = KindVocabulary("georeference");
      if (const Node n = b.Find("latitude")) {
        geo.latitude_deg = SampleInRange(n, vocabulary.Key("latitude"), rng_);
      } else {
        b.Fail("a georeference needs a latitude and a longitude (WGS84, deg)");
      }
      if (const Node n = b.Find("longitude")) {
        geo.longitude_deg = SampleInRange(n, vocabulary.Key("longitude"), rng_);
      } else {
        b.Fail("a georeference needs a latitude and a longitude (WGS84, deg)");
      }
      if (const Node n = b.Find("altitude")) geo.altitude_m = SampleScalar(n, rng_);
      plan_->geo = geo;
    } else if (def.kind == "terrain") {
      EvaluateTerrain(b);
    } else if (def.kind == "object") {
      EvaluateObject(def);
    }
  }

  // A sampled number of the key `key` of the table `kind`, within its range.
  double Sampled(const Node& n, const char* kind, const char* key) {
    return SampleInRange(n, KindVocabulary(kind).Key(key), rng_);
  }
  void EvaluateTerrain(const Node& b) {
    PlannedTerrain& t = plan_->terrain;
    t.present = true;
    t.perlin_seed =
        MixKey(seed_, static_cast<uint64_t>(StreamTag::kTerrain)) >> 11;  // 53 bits: exact in JSON
    if (const Node n = b.Find("size")) {
      t.size = SampleVec2(n, rng_);
      CheckRange(n, KindVocabulary("terrain").Key("size"), t.size.minCoeff());
    }
    if (const Node n = b.Find("height")) {
      CheckKeys(n, KindVocabulary("terrain_height"), "terrain height");
      if (const Node p = n.Find("perlin")) Perlin(p);
      if (const Node f = n.Find("frequency"))
        t.perlin_frequency = Sampled(f, "terrain_height", "frequency");
    }
    if (const Node p = b.Find("perlin")) Perlin(p);
    if (const Node f = b.Find("frequency")) t.perlin_frequency = Sampled(f, "terrain", "frequency");
    if (const Node m = b.Find("material")) t.material = SampleString(m, rng_);
    if (const Node s = b.Find("seed")) {
      t.perlin_seed = static_cast<uint64_t>(ReadInRange(s, KindVocabulary("terrain").Key("seed")));
    }
    for (const ClassInfo& c : plan_->classes)
      if (c.name == "terrain") t.class_id = c.id;
  }
  void Perlin(const Node& p) {
    if (p->is_object()) {
      CheckKeys(p, KindVocabulary("perlin"), "Perlin");
      if (const Node a = p.Find("amplitude"))
        plan_->terrain.perlin_amplitude = Sampled(a, "perlin", "amplitude");
      if (const Node f = p.Find("frequency"))
        plan_->terrain.perlin_frequency = Sampled(f, "perlin", "frequency");
    } else {
      plan_->terrain.perlin_amplitude = Sampled(p, "perlin", "amplitude");
    }
  }

  int64_t CountOf(const Definition& def) {
    if (const Node n = def.body.Find("count")) return SampleCount(n, rng_);
    auto it = count_nodes_.find(def.symbol);
    if (it != count_nodes_.end() && it->second) return SampleCount(it->second, rng_);
    if (many_default_.count(def.symbol)) return rng_.UniformInt(5, 15);  // MANY(X) without a count
    return 1;
  }

  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void EvaluateObject(const Definition& def) {
    const int64_t count = CountOf(def);
    const Node& b = def.body;
    bool overlap = false;
    std::string policy = "move";
    int retries = 100;
    if (const Node n = b.Find("overlap")) overlap = SampleBool(n, rng_);
    if (const Node n = b.Find("onoverlap")) policy = ReadString(n);
    if (const Node n = b.Find("retries")) {
      retries = static_cast<int>(ReadInRange(n, KindVocabulary("object").Key("retries")));
    }
    // A placement requirement: a free margin around the object (metres).
    double separation = 0;
    if (const Node n = b.Find("separation")) {
      separation = ReadInRange(n, KindVocabulary("object").Key("separation"));
      if (overlap) n.Fail("separation keeps objects apart; it needs overlap:false");
    }
    int64_t copy_number = 0;
    for (int64_t copy = 0; copy < count; ++copy) {
      Placed p;
      PlannedObject& o = p.object;
      o.symbol = def.symbol;
      o.separation = separation;
      const Node cls = b.Find("class");
      const std::string chosen = IsTagSelection(cls) ? "tags" : SampleString(cls, rng_);
      const std::vector<const gen::LibraryAsset*> assets = SelectAssets(Library(), cls, chosen);
      if (!assets.empty()) {  // one of the selected library assets, uniformly
        const gen::LibraryAsset& a = *assets[static_cast<size_t>(
            rng_.UniformInt(0, static_cast<int64_t>(assets.size()) - 1))];
        o.class_name = a.file;
        o.class_id = ClassIdOf(def.symbol, AssetClassName(a));
        o.extent = MeshExtent(def, a.file, a.metres_per_unit);  // the manifest's unit
      } else {
        o.class_name = ResolveClass(cls, chosen);  // the asset drawn
        o.class_id = ClassIdOf(def.symbol, ClassNameOf(cls, chosen));
        o.extent = gen::IsMeshPath(o.class_name) ? MeshExtent(def, o.class_name, MetresPerUnit(def))
                                                 : BuiltinClasses().at(o.class_name);
      }
      if (const Node n = FindKey(b, KindVocabulary("object"), "visible"))
        o.visible = SampleBool(n, rng_);
      if (const Node n = b.Find("material")) o.material = SampleString(n, rng_);
      o.target = o.visible && (targets_.empty() || targets_.count(def.symbol) > 0);
      if (const Node n = b.Find("target")) o.target = SampleBool(n, rng_);
      // Geometry keys in the order written: a size given after `position` is
      // applied after the collision test (the paper's trick for gaps or
      // overlaps, section 3.1).
      bool positioned = false, keep = true;
      for (const auto& [key, n] : b.Members()) {
        const std::string k = CanonicalKey(key);
        if (k == "extent") Resize(&p, SizeVec(n), positioned);
        if (k == "bound") Resize(&p, FirstCopy(ReadString(n)).object.extent, positioned);
        if (k == "scale") {
          const Eigen::Vector3d s = SampleScale(n, rng_);
          CheckRange(n, KindVocabulary("object").Key("scale"), s.minCoeff());
          Resize(&p, o.extent.cwiseProduct(s), positioned);
        }
        if (k == "rotation") {
          o.world_from_object = RotationFromEulerDeg(SampleVec3(n, rng_));
          if (positioned) Reseat(&p);
        }
        if (k == "position") {
          keep = Position(def, n, copy, count, overlap, policy, retries, &p);
          positioned = true;
        }
      }
      if (!positioned)
        keep = Position(
            def, Node{b.src, nullptr, b.pointer}, copy, count, overlap, policy, retries, &p);
      if (!keep) continue;
      o.name = def.symbol + "#" + std::to_string(++copy_number);
      by_symbol_[def.symbol].push_back(placed_.size());
      if (o.visible)
        grid_.Insert(static_cast<uint32_t>(placed_.size()), FootprintOf(p.aabb, o.separation));
      placed_.push_back(p);
    }
  }

  Eigen::Vector3d SizeVec(const Node& n) {
    Eigen::Vector3d e = SampleVec3(n, rng_);
    CheckRange(n, KindVocabulary("object").Key("extent"), e.minCoeff());
    return e;
  }

  // Changes the size; once placed, keeps the base where it is.
  void Resize(Placed* p, const Eigen::Vector3d& extent, bool positioned) {
    p->object.extent = extent;
    if (positioned) Reseat(p);
  }
  void Reseat(Placed* p) {
    const double old_base = p->aabb.lo.z();
    p->aabb = AabbOf(p->object.position, p->object.world_from_object, p->object.extent);
    p->object.position.z() += old_base - p->aabb.lo.z();
    p->aabb = AabbOf(p->object.position, p->object.world_from_object, p->object.extent);
  }

  const Placed& FirstCopy(const std::string& symbol) const {
    auto it = by_symbol_.find(symbol);
    if (it == by_symbol_.end() || it->second.empty())
      throw Error("'" + symbol + "' has no placed copies to refer to (count 0 or all deleted)",
                  scene_.Find(symbol)->statement.Where());
    return placed_[it->second.front()];
  }
  const Placed& AnyCopy(const Node& where, const std::string& symbol) {
    auto it = by_symbol_.find(symbol);
    if (it == by_symbol_.end() || it->second.empty())
      where.Fail("'" + symbol + "' has no placed copies to refer to (count 0 or all deleted)");
    return placed_[it->second[static_cast<size_t>(
        rng_.UniformInt(0, static_cast<int64_t>(it->second.size()) - 1))]];
  }

  Surface TerrainSurface() const {
    Surface s;
    if (plan_->terrain.present) {
      s.footprint.lo.head<2>() = -0.5 * plan_->terrain.size;
      s.footprint.hi.head<2>() = 0.5 * plan_->terrain.size;
      s.terrain = true;
    } else {  // no terrain: a 100 m x 100 m ground plane at z = 0
      s.footprint.lo.head<2>() = Eigen::Vector2d(-50, -50);
      s.footprint.hi.head<2>() = Eigen::Vector2d(50, 50);
    }
    return s;
  }

  // ON:X - the surface an object on X stands on. An invisible X (a placement
  // zone) passes on the surface X itself stands on, restricted to X's
  // footprint.
  Surface SurfaceOf(const Node& where, const std::string& symbol) {
    if (symbol == terrain_symbol_) return TerrainSurface();
    return SurfaceOf(AnyCopy(where, symbol));
  }
  Surface SurfaceOf(const Placed& x) const {
    Surface s;
    s.footprint = x.aabb;
    if (!x.object.visible && x.has_support) {
      s.footprint.Intersect(x.support.footprint);
      s.terrain = x.support.terrain;
      s.top = x.support.top;
    } else {
      s.top = x.aabb.hi.z();
    }
    s.footprint.lo.z() = -kHuge;
    s.footprint.hi.z() = kHuge;
    return s;
  }

  // Algorithm 1: start from the largest box, shrink it by each constraint in
  // order, sample a point, then resolve overlaps (move with retries, delete,
  // hide or allow). Returns false when deleted.
  // Over the bound until the evaluators are split (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  bool Position(const Definition& def,
                const Node& pos,
                int64_t copy,
                int64_t count,
                bool overlap,
                const std::string& policy,
                int retries,
                Placed* p) {
    PlannedObject& o = p->object;
    Box space;
    bool on = false, in = false;
    Surface surface;
    std::set<std::string> supports;
    std::vector<std::pair<Relation, std::string>> relations;  // and their text, for messages
    std::optional<Eigen::Vector3d> facing;                    // the point the object turns to
    struct Sight {
      Eigen::Vector3d eye;
      const Placed* viewer = nullptr;  // the object seen from (never blocks its own view)
      std::string what;
    };
    std::vector<Sight> sights;  // VISIBLE FROM
    auto shrink = [&](const Box& box, const Node& constraint, const std::string& what) {
      space.Intersect(box);
      if (space.Empty())
        constraint.Fail(def.symbol + " copy " + std::to_string(copy + 1) +
                        ": the position space is empty after " + what + " (it leaves " +
                        space.ToString() + ")");
    };
    if (pos) {
      for (const auto& [key, c] : pos.Members()) {
        const std::string k = CanonicalKey(key);
        if (k == "on") {
          const std::string ref = ReadString(c);
          surface = SurfaceOf(c, ref);
          shrink(surface.footprint, c, "ON:" + ref);
          on = true;
          supports.insert(ref);
        } else if (k == "in") {
          const std::string ref = ReadString(c);
          const Placed* x = ref == terrain_symbol_ ? nullptr : &AnyCopy(c, ref);
          if (!x || (!x->object.visible && x->has_support)) {
            // IN the terrain, or IN a zone (an invisible object standing on something), is
            // standing on that ground: within the zone's footprint, its base on the ground.
            surface = x ? SurfaceOf(*x) : TerrainSurface();
            shrink(surface.footprint, c, "IN:" + ref);
            on = true;
          } else {
            shrink(x->aabb, c, "IN:" + ref);
            in = true;
          }
          supports.insert(ref);
        } else if (k == "around") {
          std::vector<std::pair<std::string, Node>> refs;
          if (c->is_object())
            refs = c.Members();
          else
            refs.push_back({ReadString(c), Node{}});
          for (const auto& [ref, margin_node] : refs) {
            Eigen::Vector3d margin(10, 10, 0);  // default: 10 m around, horizontally
            if (margin_node) {
              if (margin_node->is_array()) {
                margin = SampleVec3(margin_node, rng_);
              } else {
                const double m = SampleScalar(margin_node, rng_);
                margin = Eigen::Vector3d(m, m, 0);
              }
              if (margin.minCoeff() < 0) margin_node.Fail("AROUND margin must be >= 0");
            }
            Box box = AnyCopy(c, ref).aabb;
            box.lo -= margin;
            box.hi += margin;
            box.lo.z() = -kHuge;  // AROUND restricts x and y; z comes from
                                  // ON/IN or the ground
            box.hi.z() = kHuge;
            shrink(box, c, "AROUND:" + ref);
          }
        } else if (IsRelationKey(k)) {
          std::vector<std::pair<std::string, Node>> refs;
          if (c->is_object())
            refs = c.Members();
          else
            refs.push_back({ReadString(c), Node{}});
          for (const auto& [ref, distance_node] : refs) {
            Relation r;
            r.kind = k == "near"     ? Relation::Kind::kNear
                     : k == "behind" ? Relation::Kind::kBehind
                                     : Relation::Kind::kInFront;
            if (k == "near") r.distance = 10;  // default: within 10 m, as AROUND
            if (distance_node) {
              r.distance = SampleScalar(distance_node, rng_);
              if (!(r.distance >= 0)) distance_node.Fail(key + " distance must be >= 0 (m)");
            }
            const PlannedObject& x = AnyCopy(c, ref).object;
            r.ref_xy = x.position.head<2>();
            r.ref_heading = HeadingOf(x.world_from_object);
            Box box;
            Eigen::Vector2d lo, hi;
            RelationBounds(r, &lo, &hi);
            box.lo.head<2>() = lo.cwiseMax(box.lo.head<2>());
            box.hi.head<2>() = hi.cwiseMin(box.hi.head<2>());
            const std::string what = key + ":" + ref;
            shrink(box, c, what);
            relations.push_back({r, what});
          }
        } else if (k == "visiblefrom") {
          Sight sight;
          if (c->is_array()) {
            for (size_t i = 0; i < 3; ++i) sight.eye[i] = ReadNumber(c.Item(i));
            sight.what = key + ":" + c->dump();
          } else {
            sight.viewer = &AnyCopy(c, ReadString(c));
            sight.eye = sight.viewer->object.position;
            sight.what = key + ":" + ReadString(c);
          }
          sights.push_back(sight);
        } else if (k == "facing") {
          if (c->is_array()) {
            Eigen::Vector3d point = Eigen::Vector3d::Zero();
            for (size_t i = 0; i < c->size(); ++i) point[i] = ReadNumber(c.Item(i));
            facing = point;
          } else {
            facing = AnyCopy(c, ReadString(c)).object.position;
          }
        } else if (k == "within") {
          if (!c->is_array() || c->size() != 2) c.Fail("within is [[x0,y0,z0],[x1,y1,z1]]");
          Box box;
          for (int i = 0; i < 3; ++i) {
            box.lo[i] = ReadNumber(c.Item(0).Item(i));
            box.hi[i] = ReadNumber(c.Item(1).Item(i));
          }
          shrink(box, c, "within");
        }
      }
    }
    if (!on && !in && space.lo.z() <= -kHuge) {  // no vertical constraint: stand on the ground
      surface = TerrainSurface();
      shrink(surface.footprint, pos ? pos : def.body, "ON:terrain (implied)");
      on = true;
      if (!terrain_symbol_.empty()) supports.insert(terrain_symbol_);
    }
    p->has_support = on;
    p->support = surface;
    // What stands ON (or IN) this object, when it is a zone, stands on this surface within the
    // zone's own box: the surface's footprint, not the space the zone's centre was drawn in
    // (a zone placed at one point has a one-point space).
    o.placement_lo = space.lo;
    o.placement_hi = space.hi;
    o.on_overlap = policy;
    o.retries = retries;
    o.relations = relations;
    o.facing = facing;
    o.sights.clear();
    for (const Sight& sight : sights)
      o.sights.push_back(
          {sight.eye, sight.viewer ? sight.viewer->object.name : std::string(), sight.what});

    // FACING turns the object after its centre is drawn; it is drawn with the
    // half-width no turn exceeds, so the turned box stays in the space.
    const Eigen::Matrix3d unturned = o.world_from_object;
    const std::string* broken = nullptr;  // the relation the last draw broke
    for (int attempt = 0;; ++attempt) {
      o.world_from_object = unturned;
      Eigen::Vector3d half = o.world_from_object.cwiseAbs() * (0.5 * o.extent);
      if (facing) half.head<2>().setConstant(HorizontalRadius(o.world_from_object, o.extent));
      for (int i = 0; i < 3; ++i) {
        if (i == 2 && on) continue;
        const double lo = space.lo[i] + half[i], hi = space.hi[i] - half[i];
        if (std::abs(space.lo[i]) >= kHuge || std::abs(space.hi[i]) >= kHuge)
          (pos ? pos : def.body)
              .Fail(def.symbol + ": the position space is unbounded along " + "xyz"[i] +
                    "; add ON, IN or within");
        o.position[i] = lo <= hi ? rng_.Uniform(lo, hi) : 0.5 * (space.lo[i] + space.hi[i]);
      }
      if (on) {
        const double ground = surface.terrain
                                  ? TerrainHeight(plan_->terrain, o.position.x(), o.position.y())
                                  : surface.top;
        o.position.z() = ground + half.z();
      }
      // A turn about the vertical keeps the box's height, so the base stays.
      if (facing) o.world_from_object = FacingRotation(unturned, o.position, *facing);
      broken = nullptr;
      for (const auto& [relation, what] : relations)
        if (!RelationHolds(relation, o.position)) broken = &what;
      if (broken) {  // a draw outside a relation's region: draw again
        if (attempt >= retries) break;
        continue;
      }
      p->aabb = AabbOf(o.position, o.world_from_object, o.extent);
      o.support = !on               ? PlannedObject::Support::kNone
                  : surface.terrain ? PlannedObject::Support::kTerrain
                                    : PlannedObject::Support::kTop;
      o.support_top = surface.top;
      o.supports.assign(supports.begin(), supports.end());
      o.overlap_allowed = overlap || policy == "allow";
      for (const Sight& sight : sights)
        if (Blocked(sight.eye, o.position, sight.viewer)) broken = &sight.what;
      if (broken) {  // the line of sight is blocked: draw again
        if (attempt >= retries) break;
        continue;
      }
      if (overlap || policy == "allow" || !Collides(*p, supports)) return true;
      if (attempt >= retries) break;
    }
    if (policy == "delete") return false;
    if (broken)
      (pos ? pos : def.body)
          .Fail(def.symbol + ": cannot place copy " + std::to_string(copy + 1) + " of " +
                std::to_string(count) + " satisfying " + *broken + " after " +
                std::to_string(retries) + " retries in " + space.ToString() +
                "; widen the relation or the space, or raise retries");
    if (policy == "hide") {
      o.visible = false;
      o.target = false;
      return true;
    }
    (pos ? pos : def.body)
        .Fail(def.symbol + ": cannot place copy " + std::to_string(copy + 1) + " of " +
              std::to_string(count) + " without overlap after " + std::to_string(retries) +
              " retries in " + space.ToString() +
              "; enlarge the space, lower the count, set overlap:true or "
              "on_overlap:delete");
  }

  // VISIBLE FROM: whether a visible object placed so far (other than the
  // viewer) stands between the eye and the centre.
  bool Blocked(const Eigen::Vector3d& eye,
               const Eigen::Vector3d& centre,
               const Placed* viewer) const {
    for (const Placed& q : placed_)
      if (q.object.visible && &q != viewer && SegmentCrossesBox(ObbOf(q.object), eye, centre))
        return true;
    return false;
  }

  // A footprint on the ground grown by a separation, for the placement grid.
  static PlacementGrid::Rect FootprintOf(const Box& aabb, double separation) {
    return {aabb.lo.x() - separation,
            aabb.lo.y() - separation,
            aabb.hi.x() + separation,
            aabb.hi.y() + separation};
  }

  // Whether p overlaps a visible object placed before it. Each footprint is in the grid grown by
  // its own separation and the query by p's, so the pairs within the larger of the two gaps are
  // among the neighbours the grid returns.
  bool Collides(const Placed& p, const std::set<std::string>& supports) {
    if (!p.object.visible) return false;
    grid_.Near(FootprintOf(p.aabb, p.object.separation), &near_);
    for (const uint32_t index : near_) {
      const Placed& q = placed_[index];
      if (!q.object.visible || supports.count(q.object.symbol)) continue;
      // The larger separation of the two: the gap either asks for.
      const double gap = std::max(p.object.separation, q.object.separation);
      if (q.aabb.hi.x() + gap <= p.aabb.lo.x() || p.aabb.hi.x() + gap <= q.aabb.lo.x() ||
          q.aabb.hi.y() + gap <= p.aabb.lo.y() || p.aabb.hi.y() + gap <= q.aabb.lo.y() ||
          q.aabb.hi.z() + gap <= p.aabb.lo.z() || p.aabb.hi.z() + gap <= q.aabb.lo.z())
        continue;
      OrientedBox mine = ObbOf(p.object);
      mine.half_extents.array() += gap;
      if (mine.Intersects(ObbOf(q.object))) return true;
    }
    return false;
  }

  const Program& scene_;
  uint64_t seed_;
  const TargetLabels& targets_;
  Plan* plan_;
  Rng rng_;
  std::string terrain_symbol_;
  std::map<std::string, std::string> aliases_;
  std::optional<gen::AssetLibrary> library_;             // asset_library{path}
  std::map<std::string, Eigen::Vector3d> mesh_extents_;  // by file path
  std::map<std::string, Node> count_nodes_;
  std::set<std::string> many_default_;
  std::vector<Placed> placed_;
  PlacementGrid grid_{kPlacementCellM};  // the visible ones among placed_, by ground cell
  std::vector<uint32_t> near_;           // Collides' scratch list
  std::map<std::string, std::vector<size_t>> by_symbol_;
};

}  // namespace

SceneClass ResolveSceneClass(const Program& scene, const Node& where, const std::string& option) {
  for (const Definition& def : scene.definitions) {
    if (def.kind != "classes") continue;
    for (const auto& [name, node] : def.body.Members())
      if (name == option) {
        const std::string canonical = gen::CanonicalClassName(ReadString(node));
        return {canonical.empty() ? ReadString(node) : canonical, option};
      }
  }
  if (const std::string canonical = gen::CanonicalClassName(option);
      BuiltinClasses().count(canonical))
    return {canonical, canonical};
  if (gen::IsMeshPath(option)) {
    const std::string path = (std::filesystem::path(scene.src->path).parent_path() / option)
                                 .lexically_normal()
                                 .generic_string();
    return {path, path};
  }
  std::vector<std::string> names;
  for (const auto& [name, extent] : BuiltinClasses()) names.push_back(name);
  where.Fail("unknown class '" + option + "'" + DidYouMean(option, names) +
             "; use a built-in class, a mesh file (" + Join(gen::MeshExtensions(), " ") +
             ", relative to the scene file) or a classes{...} alias of the scene");
}

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
