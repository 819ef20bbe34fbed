#include "generator/lang/capture/targets.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "libs/util/strings.h"

namespace lsds {
namespace {

uint32_t LabelId(const Node& where, double value) {
  if (!(value >= 1 && value <= 4294967295.0) || value != std::floor(value))
    where.Fail("a label id must be a whole number in [1, 4294967295]");
  return static_cast<uint32_t>(value);
}

// One target: its symbol, checked against the scene, and its label: `label` a number, a
// {class: id} object, or null (none).
void ReadTarget(const Program& scene,
                const Node& where,
                const std::string& symbol,
                const Node& label,
                TargetLabels* labels) {
  const Definition* def = scene.Find(symbol);
  if (!def || def->kind != "object") {
    std::vector<std::string> names;
    for (const Definition& s : scene.definitions)
      if (s.kind == "object") names.push_back(s.symbol);
    where.Fail("target '" + symbol + "' is not an object of the scene" + DidYouMean(symbol, names));
  }
  TargetLabel& t = (*labels)[symbol];
  t.where = label ? label : where;
  if (!label) return;
  if (label->is_object()) {
    if (label->empty()) label.Fail("a label per class is {class: id, ...}");
    for (const auto& [name, id] : label.Members()) t.by_class[name] = LabelId(id, ReadNumber(id));
  } else {
    t.first_id = LabelId(label, ReadNumber(label));
  }
}

// A list item: `O1`, `O1:5` (text), or {O1: 5} / {V1: {car: 1, truck: 2}}.
void ReadTargetItem(const Program& scene, const Node& item, TargetLabels* labels) {
  if (item->is_object() && item->size() == 1) {
    const auto [symbol, label] = item.Members().front();
    ReadTarget(scene, item, symbol, label, labels);
    return;
  }
  const std::string text = ReadString(item);
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return ReadTarget(scene, item, text, Node{}, labels);
  const std::string number = text.substr(colon + 1);
  char* end = nullptr;
  const double id = std::strtod(number.c_str(), &end);
  if (number.empty() || *end != '\0') item.Fail("expected NAME:NUMBER, found '" + text + "'");
  ReadTarget(scene, item, text.substr(0, colon), Node{}, labels);
  (*labels)[text.substr(0, colon)].first_id = LabelId(item, id);
}

}  // namespace

TargetLabels ReadTargets(const Program& capture, const Program& scene) {
  TargetLabels labels;
  for (const Definition& d : capture.definitions) {
    if (d.kind != "camera") continue;
    const Node t = d.body.Find("targets");
    if (!t) continue;
    if (t->is_array()) {
      for (size_t i = 0; i < t->size(); ++i) ReadTargetItem(scene, t.Item(i), &labels);
    } else if (t->is_object()) {
      for (const auto& [key, value] : t.Members()) ReadTarget(scene, value, key, value, &labels);
    } else {
      t.Fail("targets are a list [O1:5, V1:{car:1,truck:2}, O2]");
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
