#include "generator/lang/scene/blueprints.h"

#include "generator/lang/vocabulary.h"
#include "generator/plan/terrain_height.h"

namespace lsds {

void CheckBlueprint(const Definition& blueprint, const ClassCatalog& catalog) {
  if (blueprint.body->empty())
    blueprint.body.Fail("a blueprint lists its members: NAME:{class:..., at:[x,y,z]}, ...");
  for (const auto& [name, member] : blueprint.body.Members()) {
    if (!member->is_object())
      member.Fail(
          "a blueprint member is an object block {class, at, rotation, extent, scale, "
          "material}");
    CheckKeys(
        member, KindVocabulary("blueprint_member"), "member " + name + " of " + blueprint.symbol);
    const Node cls = member.Find("class");
    if (!cls) member.Fail("member " + name + " of " + blueprint.symbol + " needs a class");
    for (const std::string& option : StringOptions(cls)) {
      if (catalog.Blueprint(option))
        cls.Fail("a blueprint's member is an object, not another blueprint ('" + option + "')");
      catalog.Candidates(cls, option);  // resolves, or a located error
    }
  }
}

std::vector<Node> BlueprintClassNodes(const Definition& blueprint) {
  std::vector<Node> nodes;
  for (const auto& [name, member] : blueprint.body.Members()) nodes.push_back(member.Find("class"));
  return nodes;
}

DrawnBlueprint DrawBlueprint(const Definition& blueprint, ClassCatalog* catalog, Rng& rng) {
  DrawnBlueprint out;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kHuge), hi = -lo;
  const KindSpec& vocabulary = KindVocabulary("blueprint_member");
  for (const auto& [name, member] : blueprint.body.Members()) {
    BlueprintMember m;
    m.name = name;
    const Node cls = member.Find("class");
    const std::vector<SceneClass> candidates = catalog->Candidates(cls, SampleString(cls, rng));
    m.drawn = candidates[static_cast<size_t>(
        rng.UniformInt(0, static_cast<int64_t>(candidates.size()) - 1))];
    m.extent = catalog->NaturalExtent(m.drawn.asset,
                                      catalog->LibraryMetresPerUnit(m.drawn.asset),
                                      cls,
                                      "member " + name + " of " + blueprint.symbol,
                                      rng.KeyHere(ClassCatalog::kMemberKeyPurpose));
    if (const Node n = member.Find("extent")) m.extent = SampleVec3(n, rng);
    if (const Node n = member.Find("scale")) m.extent = m.extent.cwiseProduct(SampleScale(n, rng));
    if (!(m.extent.minCoeff() > 0)) member.Fail("member " + name + ": a size must be > 0");
    if (const Node n = member.Find("rotation"))
      m.group_from_member = RotationFromEulerDeg(SampleVec3(n, rng));
    if (const Node n = member.Find("material")) m.material = SampleString(n, rng);
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    if (const Node n = FindKey(member, vocabulary, "at")) at = SampleVec3(n, rng);
    const Eigen::Vector3d half = m.group_from_member.cwiseAbs() * (0.5 * m.extent);
    m.base_in_group = at.z();
    m.centre_in_group = at + Eigen::Vector3d(0, 0, half.z());
    lo = lo.cwiseMin(m.centre_in_group - half);
    hi = hi.cwiseMax(m.centre_in_group + half);
    out.members.push_back(std::move(m));
  }
  lo.z() = std::min(lo.z(), 0.0);  // the group's base: its frame's z = 0
  out.extent = (hi - lo).cwiseMax(Eigen::Vector3d::Constant(1e-3));
  out.centre_in_group = 0.5 * (lo + hi);
  return out;
}

std::vector<PlannedObject> PlaceMembers(const DrawnBlueprint& blueprint,
                                        const Placed& group,
                                        const PlannedTerrain& terrain) {
  const PlannedObject& g = group.object;
  const Eigen::Matrix3d& world_from_group = g.world_from_object;
  // The group frame's origin: below the box centre by the centre's height above the base.
  const double group_base = group.aabb.lo.z();
  std::vector<PlannedObject> members;
  for (const BlueprintMember& m : blueprint.members) {
    PlannedObject o;
    o.symbol = g.symbol;
    o.name = g.name + "/" + m.name;
    o.class_name = m.drawn.asset;
    o.extent = m.extent;
    o.world_from_object = world_from_group * m.group_from_member;
    o.position = g.position + world_from_group * (m.centre_in_group - blueprint.centre_in_group);
    const double half_z = (o.world_from_object.cwiseAbs() * (0.5 * o.extent)).z();
    double base = group_base + m.base_in_group;  // standing on nothing: as drawn
    if (g.support == PlannedObject::Support::kTerrain)
      base = TerrainHeight(terrain, o.position.x(), o.position.y()) + m.base_in_group;
    else if (g.support == PlannedObject::Support::kTop)
      base = g.support_top + m.base_in_group;
    o.position.z() = base + half_z;
    o.material = m.material;
    o.visible = g.visible;
    o.target = g.target;
    o.support = g.support;
    o.support_top = g.support_top;
    o.supports = g.supports;
    o.placement_lo = o.placement_hi = o.position;  // its place is the group's
    o.on_overlap = "allow";
    o.overlap_allowed = true;  // the group was placed; its members are where the blueprint says
    members.push_back(std::move(o));
  }
  return members;
}

}  // namespace lsds
