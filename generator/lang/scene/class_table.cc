#include "generator/lang/scene/class_table.h"

#include <algorithm>
#include <set>
#include <vector>

#include "generator/lang/scene/blueprints.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// The class names an object's class node may label it with, each once, in order.
// A blueprint's are its members' (blueprints.h).
std::vector<std::string> ClassNamesOf(const ClassCatalog& catalog, const Node& cls) {
  std::vector<std::string> names;
  auto add = [&names](const std::string& name) {
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  for (const std::string& option : StringOptions(cls)) {
    if (const Definition* blueprint = catalog.Blueprint(option)) {
      for (const Node& member : BlueprintClassNodes(*blueprint))
        for (const std::string& member_option : StringOptions(member))
          for (const SceneClass& candidate : catalog.Candidates(member, member_option))
            add(candidate.name);
      continue;
    }
    for (const SceneClass& candidate : catalog.Candidates(cls, option)) add(candidate.name);
  }
  return names;
}

}  // namespace

LabelIds LabelIdsOf(const Program& scene,
                    const ClassCatalog& catalog,
                    const std::string& symbol,
                    const TargetLabel& label) {
  const std::vector<std::string> names =
      ClassNamesOf(catalog, scene.Find(symbol)->body.Find("class"));
  LabelIds ids;
  if (label.by_class.empty()) {
    for (const std::string& name : names) ids[name] = label.first_id;
    return ids;
  }
  for (const std::string& name : names)
    if (!label.by_class.count(name))
      label.where.Fail(symbol + " may draw '" + name + "', which its label does not name; label " +
                       "each class it draws: {" + Join(names, ":ID, ") + ":ID}");
  for (const auto& [name, id] : label.by_class)
    if (std::find(names.begin(), names.end(), name) == names.end())
      label.where.Fail(symbol + " never draws '" + name + "'" + DidYouMean(name, names) +
                       "; it draws " + Join(names, ", "));
  return label.by_class;
}

TargetClassIds AssignClassIds(const Program& scene,
                              const ClassCatalog& catalog,
                              const TargetLabels& targets,
                              Plan* plan) {
  TargetClassIds labelled;
  std::map<uint32_t, std::vector<std::string>> labelled_names;  // label id -> the classes it labels
  for (const auto& [symbol, label] : targets) {
    if (!label.labelled()) continue;
    labelled[symbol] = LabelIdsOf(scene, catalog, symbol, label);
    for (const auto& [name, id] : labelled[symbol]) {
      std::vector<std::string>& names = labelled_names[id];
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  }
  uint32_t next = 1;
  auto add = [&](const std::string& name) {
    for (const ClassInfo& c : plan->classes)
      if (c.name == name) return;
    while (labelled_names.count(next)) ++next;
    plan->classes.push_back({next++, name});
  };
  for (const Definition& def : scene.definitions) {
    if (def.kind == "terrain") add("terrain");
    if (def.kind != "object" || labelled.count(def.symbol)) continue;
    for (const std::string& name : ClassNamesOf(catalog, def.body.Find("class"))) add(name);
  }
  for (const auto& [id, names] : labelled_names) {
    std::string name = Join(names, "|");
    // A label may not take a name of the table.
    for (const ClassInfo& c : plan->classes)
      if (c.name == name) name += "#" + std::to_string(id);
    plan->classes.push_back({id, name});
  }
  std::sort(plan->classes.begin(), plan->classes.end(), [](const ClassInfo& a, const ClassInfo& b) {
    return a.id < b.id;
  });
  return labelled;
}

uint32_t ClassIdOf(const Plan& plan,
                   const TargetClassIds& labelled,
                   const std::string& symbol,
                   const std::string& class_name) {
  if (const auto target = labelled.find(symbol); target != labelled.end()) {
    const auto id = target->second.find(class_name);
    if (id != target->second.end()) return id->second;
  }
  for (const ClassInfo& c : plan.classes)
    if (c.name == class_name) return c.id;
  return 0;
}

}  // namespace lsds
