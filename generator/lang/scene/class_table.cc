#include "generator/lang/scene/class_table.h"

#include <algorithm>
#include <set>
#include <vector>

#include "libs/util/strings.h"

namespace lsds {
namespace {

// The class names an object's class node may label it with, each once, in order.
std::vector<std::string> ClassNamesOf(const ClassCatalog& assets, const Node& cls) {
  std::vector<std::string> names;
  for (const std::string& option : StringOptions(cls))
    for (const SceneClass& candidate : assets.Candidates(cls, option))
      if (std::find(names.begin(), names.end(), candidate.name) == names.end())
        names.push_back(candidate.name);
  return names;
}

}  // namespace

LabelIds LabelIdsOf(const Program& scene,
                    const ClassCatalog& assets,
                    const std::string& symbol,
                    const TargetLabel& label) {
  const std::vector<std::string> names =
      ClassNamesOf(assets, scene.Find(symbol)->body.Find("class"));
  LabelIds ids;
  if (label.by_class.empty()) {
    uint64_t id = label.first_id;
    for (const std::string& name : names) {
      if (id > 0xFFFFFFFFull) label.where.Fail("the label ids of " + symbol + " pass 4294967295");
      ids[name] = static_cast<uint32_t>(id++);
    }
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
                              const ClassCatalog& assets,
                              const TargetLabels& targets,
                              Plan* plan) {
  TargetClassIds labelled;
  std::map<uint32_t, std::string> owner;  // label id -> the target that has it
  for (const auto& [symbol, label] : targets) {
    if (!label.labelled()) continue;
    labelled[symbol] = LabelIdsOf(scene, assets, symbol, label);
    for (const auto& [name, id] : labelled[symbol]) {
      const auto [it, added] = owner.emplace(id, symbol);
      if (!added)
        label.where.Fail("label id " + std::to_string(id) + " of " + symbol + " (" + name +
                         ") is also " + it->second + "'s; give each labelled class its own id");
    }
  }
  uint32_t next = 1;
  auto add = [&](const std::string& name) {
    for (const ClassInfo& c : plan->classes)
      if (c.name == name) return;
    while (owner.count(next)) ++next;
    plan->classes.push_back({next++, name});
  };
  for (const Definition& def : scene.definitions) {
    if (def.kind == "terrain") add("terrain");
    if (def.kind != "object" || labelled.count(def.symbol)) continue;
    for (const std::string& name : ClassNamesOf(assets, def.body.Find("class"))) add(name);
  }
  for (const auto& [id, symbol] : owner)
    for (const auto& [class_name, class_id] : labelled.at(symbol)) {
      if (class_id != id) continue;
      std::string name = class_name;
      // Two labels may not share a name, nor a label a name of the table.
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
