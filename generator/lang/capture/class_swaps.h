// Class and asset swaps of LCAP scene changes (`O1:{class:{truck:0.5, car:0.5}}`,
// `class:{tags:[desert]}`): what a change may draw, and the class id each drawn class takes in the
// plan's class table.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "generator/lang/scene.h"
#include "generator/lang/scene/class_catalog.h"

namespace lsds {

class ClassSwaps {
 public:
  // `labels` are the capture's target labels; classes a swap draws join `plan`'s table.
  ClassSwaps(const Program& scene, TargetLabels labels, Plan* plan)
      : scene_(scene), labels_(std::move(labels)), plan_(plan) {}

  // The options of a class change: its names or choice keys, or "tags" for a library tag
  // selection (`class:{tags:[desert,rock]}`).
  static std::vector<std::string> Options(const Node& cls);

  // What option `option` of class node `cls` may draw: the scene's asset library's assets it
  // selects (by name, tags or pattern, as in LSCENE), or else the one class it resolves to.
  std::vector<SceneClass> Candidates(const Node& cls, const std::string& option);

  // The asset and class id a class change draws for an object of `symbol`: a labelled target keeps
  // its label's id for a class the label names; otherwise the object takes the class of that name,
  // added to the class table if the scene has none (after the scene's ids and labels, so that
  // those never change).
  std::pair<std::string, uint32_t> Class(const std::string& symbol, const SceneClass& resolved);

  // The size a drawn class has of its own (docs/languages.md, "Class swaps and re-scatters"): a
  // built-in's box, a mesh's native bounds in metres (a library asset's in its manifest's unit).
  // The mesh's location names `where` when it cannot be read.
  // `member_key` draws a built-in family's member (ClassCatalog::NaturalExtent).
  Eigen::Vector3d NaturalExtent(const SceneClass& drawn, const Node& where, uint64_t member_key);

  // Every class a change of `symbol`'s class to `cls` may draw joins the table now, and is kept
  // shown (DropHelperClasses).
  void Declare(const std::string& symbol, const Node& cls);
  const std::set<uint32_t>& swapped_in() const { return swapped_in_; }

 private:
  // The scene's aliases and asset library, read once on first use.
  ClassCatalog& Assets();

  const Program& scene_;
  TargetLabels labels_;
  Plan* plan_;
  std::optional<ClassCatalog> assets_;
  std::map<std::string, std::map<std::string, uint32_t>> label_ids_;  // labelled targets, by class
  std::set<uint32_t> swapped_in_;  // class ids class changes may draw
};

}  // namespace lsds
