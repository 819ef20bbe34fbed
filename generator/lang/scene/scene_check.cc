#include "generator/lang/scene/scene_check.h"

#include <vector>

#include "generator/lang/asset_choice.h"
#include "generator/lang/environment.h"
#include "generator/lang/scene/blueprints.h"
#include "generator/lang/scene/position.h"
#include "generator/lang/vocabulary.h"
#include "generator/scene/mesh_formats.h"
#include "generator/scene/object_library.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

class SceneChecker {
 public:
  SceneChecker(const Program& scene, ClassCatalog* catalog) : scene_(scene), catalog_(*catalog) {}

  SceneSymbols Run() {
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
        symbols_.terrain = def.symbol;
      }
      if (k == "classes") CheckAliases(def);
      if (k == "asset_library") {
        if (catalog_.HasLibrary()) def.statement.Fail("only one asset_library per scene");
        catalog_.SetLibrary(LoadSceneAssetLibrary(scene_, def));
      }
      if (k == "blueprint") {
        CheckBlueprint(def, catalog_);
        catalog_.AddBlueprint(def);
      }
      if (k == "object") CheckObject(def, defined);
      defined.insert(def.symbol);
    }
    CheckStartRule();
    return symbols_;
  }

 private:
  void CheckAliases(const Definition& def) {
    for (const auto& [name, node] : def.body.Members()) {
      const std::string target = ReadString(node);
      if (!BuiltinClasses().count(gen::CanonicalClassName(target)) && !gen::IsMeshPath(target))
        node.Fail("class alias '" + name + "' must name a built-in class or a mesh file, not '" +
                  target + "'" + DidYouMean(target, ClassCatalog::BuiltinNames()));
      catalog_.AddAlias(name, target);
    }
  }

  void CheckReference(const Node& node,
                      const std::set<std::string>& defined,
                      const std::string& symbol,
                      bool objects_only) const {
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

  void CheckObject(const Definition& def, const std::set<std::string>& defined) {
    CheckKeys(def.body, KindVocabulary("object"), "object " + def.symbol);
    CheckClass(def);
    if (const Node pos = def.body.Find("position")) CheckPosition(def, pos, defined);
    if (const Node bound = def.body.Find("bound")) CheckReference(bound, defined, def.symbol, true);
    if (const Node policy = def.body.Find("onoverlap")) {
      const std::string p = ReadString(policy);
      if (p != "move" && p != "delete" && p != "hide" && p != "allow")
        policy.Fail("on_overlap must be move, delete, hide or allow" +
                    DidYouMean(p, {"move", "delete", "hide", "allow"}));
    }
  }

  // A class: a name or a choice {name: weight}, each option a library selection or a class that
  // resolves.
  void CheckClass(const Definition& def) const {
    const Node cls = def.body.Find("class");
    if (!cls) def.body.Fail("object " + def.symbol + " needs a class (e.g. class:cube)");
    if (!cls->is_string() && !cls->is_object())
      cls.Fail("class must be a name or a choice {name: weight}");
    if (IsTagSelection(cls)) {
      SelectAssets(catalog_.Library(), cls, "tags");
    } else if (cls->is_object()) {
      for (const auto& [key, weight] : cls.Members()) (void)key, ReadNumber(weight);
    }
    for (const std::string& option : StringOptions(cls)) {
      if (catalog_.Blueprint(option)) continue;  // a group of objects (blueprints.h)
      if (!SelectAssets(catalog_.Library(), cls, option).empty()) continue;  // a library selection
      if (cls->is_object()) {
        try {
          catalog_.Resolve(cls.Child(option), option);
        } catch (const Error& e) {  // point at the option's name, not its weight
          throw Error(e.message(), cls.src->WhereKey(cls.Child(option).pointer));
        }
      } else {
        catalog_.Resolve(cls, option);
      }
    }
  }

  void CheckPosition(const Definition& def, const Node& pos, const std::set<std::string>& defined) {
    CheckKeys(pos, KindVocabulary("position"), "position of " + def.symbol);
    for (const auto& [key, c] : pos.Members()) {
      const std::string k = CanonicalKey(key);
      if (k == "within" || k == "wgs84") continue;  // numbers, read when placing
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
      for (const Definition* d : StartRuleDefinitions(sym)) {
        if (many && d->kind != "object")
          sym.Fail("MANY applies to objects only; '" + d->symbol + "' is a " + d->kind);
        if (d->kind != "object") continue;
        symbols_.start_counts[d->symbol] = many ? entry.Child("count") : Node{};
        if (many && !entry.Child("count")) symbols_.many_without_count.insert(d->symbol);
      }
    }
  }

  // The definitions a start rule entry names: one symbol, or every definition of a Table 1
  // category.
  std::vector<const Definition*> StartRuleDefinitions(const Node& sym) const {
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
    return defs;
  }

  const Program& scene_;
  ClassCatalog& catalog_;
  SceneSymbols symbols_;
};

}  // namespace

SceneSymbols CheckScene(const Program& scene, ClassCatalog* catalog) {
  return SceneChecker(scene, catalog).Run();
}

}  // namespace lsds
