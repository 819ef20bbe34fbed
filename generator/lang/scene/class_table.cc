#include "generator/lang/scene/class_table.h"

#include <algorithm>
#include <set>
#include <vector>

#include "libs/util/strings.h"

namespace lsds {
namespace {

uint32_t LabelOf(const TargetLabels& targets, const std::string& symbol) {
  const auto t = targets.find(symbol);
  return t == targets.end() ? 0 : t->second;
}

// The class names an object's class node may label it with, each once, in order.
std::vector<std::string> ClassNamesOf(const SceneAssets& assets, const Node& cls) {
  std::vector<std::string> names;
  for (const std::string& option : StringOptions(cls))
    for (const SceneClass& candidate : assets.Candidates(cls, option))
      if (std::find(names.begin(), names.end(), candidate.name) == names.end())
        names.push_back(candidate.name);
  return names;
}

}  // namespace

void AssignClassIds(const Program& scene,
                    const SceneAssets& assets,
                    const TargetLabels& targets,
                    Plan* plan) {
  std::set<uint32_t> reserved;
  for (const auto& [symbol, label] : targets)
    if (label != 0) reserved.insert(label);
  uint32_t next = 1;
  auto add = [&](const std::string& name) {
    for (const ClassInfo& c : plan->classes)
      if (c.name == name) return;
    while (reserved.count(next)) ++next;
    plan->classes.push_back({next++, name});
  };
  for (const Definition& def : scene.definitions) {
    if (def.kind == "terrain") add("terrain");
    if (def.kind != "object" || LabelOf(targets, def.symbol) != 0) continue;
    for (const std::string& name : ClassNamesOf(assets, def.body.Find("class"))) add(name);
  }
  for (const auto& [symbol, label] : targets) {
    const Definition* def = scene.Find(symbol);
    if (!def || label == 0) continue;
    std::string name = Join(ClassNamesOf(assets, def->body.Find("class")), "|");
    // Two labels may not share a name, nor a label a name of the table.
    for (const ClassInfo& c : plan->classes)
      if (c.name == name) name += "#" + std::to_string(label);
    plan->classes.push_back({label, name});
  }
  std::sort(plan->classes.begin(), plan->classes.end(), [](const ClassInfo& a, const ClassInfo& b) {
    return a.id < b.id;
  });
}

uint32_t ClassIdOf(const Plan& plan,
                   const TargetLabels& targets,
                   const std::string& symbol,
                   const std::string& class_name) {
  if (const uint32_t label = LabelOf(targets, symbol)) return label;
  for (const ClassInfo& c : plan.classes)
    if (c.name == class_name) return c.id;
  return 0;
}

}  // namespace lsds
