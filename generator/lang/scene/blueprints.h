// The paper's Blueprint Class (Table 2): a named group of objects placed together. A blueprint
// lists its members, each an object of a class at an offset in the group's frame:
//   CAMP = blueprint{TENT:{class:crate,extent:[3,2,2]}, FIRE:{class:barrel,at:[3,1,0]}}
//   C = object{class:CAMP, position:{ON:W,...}, rotation:[0,0,[0,360]]}
// places the group's box by Algorithm 1 like one object, then each member at its offset, turned
// with the group and standing on what the group stands on (docs/languages.md, "Blueprint classes").
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/lang/random.h"
#include "generator/lang/scene.h"
#include "generator/lang/scene/class_catalog.h"
#include "generator/lang/scene/placed_objects.h"

namespace lsds {

// Checks a blueprint's members: each an object block with a class the catalog resolves (not
// another blueprint), and only the member keys.
void CheckBlueprint(const Definition& blueprint, const ClassCatalog& catalog);

// The class nodes of a blueprint's members, in order.
std::vector<Node> BlueprintClassNodes(const Definition& blueprint);

struct BlueprintMember {
  std::string name;  // the member's key (TENT)
  SceneClass drawn;
  Eigen::Vector3d extent;
  Eigen::Matrix3d group_from_member = Eigen::Matrix3d::Identity();
  Eigen::Vector3d centre_in_group;  // its box centre in the group frame (base of the group: z 0)
  double base_in_group = 0;         // its base's height above the group's base
  std::string material;
};

struct DrawnBlueprint {
  std::vector<BlueprintMember> members;
  Eigen::Vector3d extent;           // the group's box, around every member
  Eigen::Vector3d centre_in_group;  // that box's centre in the group frame
};

// Draws one copy's members (class choices, sizes, rotations) from `rng`.
DrawnBlueprint DrawBlueprint(const Definition& blueprint, ClassCatalog* catalog, Rng& rng);

// The members of a group placed as `group` (its centre, rotation and support): each at the
// group's pose times its offset, its base on the group's support at its own (x, y) (the terrain's
// height there, or the top), or as drawn when the group stands on nothing.
std::vector<PlannedObject> PlaceMembers(const DrawnBlueprint& blueprint,
                                        const Placed& group,
                                        const PlannedTerrain& terrain);

}  // namespace lsds
