#include "generator/lang/capture/class_swaps.h"

#include <algorithm>

#include "generator/lang/asset_choice.h"

namespace lsds {

std::vector<std::string> ClassSwaps::Options(const Node& cls) {
  if (IsTagSelection(cls)) return {"tags"};
  return StringOptions(cls);
}

std::vector<SceneClass> ClassSwaps::Candidates(const Node& cls, const std::string& option) {
  return Assets().Candidates(cls, option);
}

SceneAssets& ClassSwaps::Assets() {
  if (!assets_) assets_ = SceneAssets::OfCheckedScene(scene_);
  return *assets_;
}

std::pair<std::string, uint32_t> ClassSwaps::Class(const std::string& symbol,
                                                   const SceneClass& resolved) {
  const auto label = labels_.find(symbol);
  if (label != labels_.end() && label->second != 0) return {resolved.asset, label->second};
  uint32_t next = 1;
  for (const ClassInfo& c : plan_->classes) {
    if (c.name == resolved.name) return {resolved.asset, c.id};
    next = std::max(next, c.id + 1);
  }
  for (const auto& [s, l] : labels_) next = std::max(next, l + 1);
  plan_->classes.push_back({next, resolved.name});
  return {resolved.asset, next};
}

Eigen::Vector3d ClassSwaps::NaturalExtent(const SceneClass& drawn, const Node& where) {
  return Assets().NaturalExtent(
      drawn.asset, Assets().LibraryMetresPerUnit(drawn.asset), where, "class change");
}

void ClassSwaps::Declare(const std::string& symbol, const Node& cls) {
  for (const std::string& option : Options(cls))
    for (const SceneClass& candidate : Candidates(cls, option))
      swapped_in_.insert(Class(symbol, candidate).second);
}

}  // namespace lsds
