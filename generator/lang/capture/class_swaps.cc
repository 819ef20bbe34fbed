#include "generator/lang/capture/class_swaps.h"

#include <algorithm>

#include "generator/lang/asset_choice.h"
#include "generator/lang/scene/class_table.h"

namespace lsds {

std::vector<std::string> ClassSwaps::Options(const Node& cls) {
  if (IsTagSelection(cls)) return {"tags"};
  return StringOptions(cls);
}

std::vector<SceneClass> ClassSwaps::Candidates(const Node& cls, const std::string& option) {
  return Assets().Candidates(cls, option);
}

ClassCatalog& ClassSwaps::Assets() {
  if (!assets_) assets_ = ClassCatalog::OfCheckedScene(scene_);
  return *assets_;
}

std::pair<std::string, uint32_t> ClassSwaps::Class(const std::string& symbol,
                                                   const SceneClass& resolved) {
  // A target with one label keeps it whatever it draws (the paper's per-pixel label); one labelled
  // per class keeps the id of a class its label names (scene/class_table.h).
  const auto label = labels_.find(symbol);
  if (label != labels_.end() && label->second.first_id != 0)
    return {resolved.asset, label->second.first_id};
  if (label != labels_.end() && label->second.labelled()) {
    auto ids = label_ids_.find(symbol);
    if (ids == label_ids_.end())
      ids = label_ids_.emplace(symbol, LabelIdsOf(scene_, Assets(), symbol, label->second)).first;
    if (const auto id = ids->second.find(resolved.name); id != ids->second.end())
      return {resolved.asset, id->second};
  }
  uint32_t next = 1;
  for (const ClassInfo& c : plan_->classes) {
    if (c.name == resolved.name) return {resolved.asset, c.id};
    next = std::max(next, c.id + 1);
  }
  plan_->classes.push_back({next, resolved.name});
  return {resolved.asset, next};
}

Eigen::Vector3d ClassSwaps::NaturalExtent(const SceneClass& drawn,
                                          const Node& where,
                                          uint64_t member_key) {
  return Assets().NaturalExtent(
      drawn.asset, Assets().LibraryMetresPerUnit(drawn.asset), where, "class change", member_key);
}

void ClassSwaps::Declare(const std::string& symbol, const Node& cls) {
  for (const std::string& option : Options(cls))
    for (const SceneClass& candidate : Candidates(cls, option))
      swapped_in_.insert(Class(symbol, candidate).second);
}

}  // namespace lsds
