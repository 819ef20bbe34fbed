#include "generator/lang/capture/targets.h"

#include <cstdint>
#include <tuple>
#include <vector>

#include "generator/lang/capture/timeline.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// One entry of a targets list or object: its symbol and label (-1: none), checked.
void ReadTarget(const Program& scene,
                const Node& where,
                const std::string& symbol,
                int64_t label,
                TargetLabels* labels) {
  const Definition* def = scene.Find(symbol);
  if (!def || def->kind != "object") {
    std::vector<std::string> names;
    for (const Definition& s : scene.definitions)
      if (s.kind == "object") names.push_back(s.symbol);
    where.Fail("target '" + symbol + "' is not an object of the scene" + DidYouMean(symbol, names));
  }
  // -1: listed without a label ("O2"); its class comes from the scene.
  if (label == 0 || label > 0xFFFFFFFFll) where.Fail("a label id must be in [1, 4294967295]");
  (*labels)[symbol] = static_cast<uint32_t>(label < 0 ? 0 : label);
}

}  // namespace

TargetLabels ReadTargets(const Program& capture, const Program& scene) {
  TargetLabels labels;
  for (const Definition& d : capture.definitions) {
    if (d.kind != "camera") continue;
    const Node t = d.body.Find("targets");
    if (!t) continue;
    if (t->is_array()) {
      for (size_t i = 0; i < t->size(); ++i) {
        const auto [symbol, label] = RefWithNumber(t.Item(i));
        ReadTarget(scene, t.Item(i), symbol, label, &labels);
      }
    } else if (t->is_object()) {
      // {O1: 5, ...}: the label is the member's number (errors at the whole object).
      for (const auto& [key, value] : t.Members())
        ReadTarget(scene, t, key, static_cast<int64_t>(ReadNumber(value)), &labels);
    } else {
      t.Fail("targets are a list [O1:5, ...]");
    }
  }
  return labels;
}

std::string FirstTarget(const Program& capture) {
  std::string first;
  for (const Definition& d : capture.definitions)
    if (d.kind == "camera")
      if (const Node t = d.body.Find("targets"); t && t->is_array() && !t->empty())
        if (t->at(0).is_string())
          first = t->at(0).get<std::string>().substr(0, t->at(0).get<std::string>().find(':'));
  return first;
}

}  // namespace lsds
