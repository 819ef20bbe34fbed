#include "generator/lang/capture/rescatter.h"

#include <algorithm>
#include <map>
#include <string>

#include "generator/plan/relations.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/oriented_box.h"

namespace lsds {
namespace {

// An object as the frame's changes so far leave it.
struct State {
  const PlannedObject* planned;
  Eigen::Vector3d position, extent;
  Eigen::Matrix3d world_from_object;
  bool visible;
};
using States = std::map<std::string, State>;

States FrameStates(const Plan& plan, const PlannedFrame& f) {
  States states;
  for (const PlannedObject& p : plan.objects)
    states[p.name] = {&p, p.position, p.extent, p.world_from_object, p.visible};
  for (const ObjectChange& change : f.changes) {
    State& s = states.at(change.object);
    if (change.position) s.position = *change.position;
    if (change.extent) s.extent = *change.extent;
    if (change.world_from_object) s.world_from_object = *change.world_from_object;
    if (change.visible) s.visible = *change.visible;
  }
  return states;
}

// A centre drawn uniformly in the placement space shrunk by `half`, seated on the support.
Eigen::Vector3d DrawPlace(const PlannedTerrain& ground,
                          const PlannedObject& o,
                          const Eigen::Vector3d& half,
                          Rng& rng) {
  const bool on = o.support != PlannedObject::Support::kNone;
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i) {
    if (i == 2 && on) continue;
    const double lo = o.placement_lo[i] + half[i], hi = o.placement_hi[i] - half[i];
    p[i] = lo <= hi ? rng.Uniform(lo, hi) : 0.5 * (o.placement_lo[i] + o.placement_hi[i]);
  }
  if (o.support == PlannedObject::Support::kTerrain)
    p.z() = TerrainHeight(ground, p.x(), p.y()) + half.z();
  else if (o.support == PlannedObject::Support::kTop)
    p.z() = o.support_top + half.z();
  return p;
}

// The text of the last relation of `o` a centre at `p` breaks; null when all hold.
const std::string* BrokenRelation(const PlannedObject& o,
                                  const Eigen::Vector3d& p,
                                  const States& states) {
  const std::string* broken = nullptr;
  for (const auto& [relation, what] : o.relations)
    if (!RelationHolds(relation, p)) broken = &what;
  for (const PlannedObject::Sight& sight : o.sights)
    for (const auto& [name, t] : states)
      if (name != o.name && name != sight.viewer && t.visible &&
          SegmentCrossesBox({t.position, 0.5 * t.extent, t.world_from_object}, sight.eye, p))
        broken = &sight.what;
  return broken;
}

// Whether `me` at `p` overlaps another visible object (its supports aside), each box grown by the
// larger LSCENE separation of the two.
bool Collides(const PlannedObject& o,
              const State& me,
              const Eigen::Vector3d& p,
              const States& states) {
  for (const auto& [name, t] : states) {
    if (name == o.name || !t.visible) continue;
    if (std::find(o.supports.begin(), o.supports.end(), t.planned->symbol) != o.supports.end())
      continue;
    const double gap = std::max(o.separation, t.planned->separation);
    const OrientedBox mine{
        p, 0.5 * me.extent + Eigen::Vector3d::Constant(gap), me.world_from_object};
    if (mine.Intersects({t.position, 0.5 * t.extent, t.world_from_object})) return true;
  }
  return false;
}

}  // namespace

void Rescatter(const Plan& plan,
               const Rule& rule,
               const PlannedObject& o,
               const PlannedFrame& f,
               Rng& rng,
               ObjectChange* c) {
  States states = FrameStates(plan, f);
  State& me = states.at(o.name);
  if (c->extent) me.extent = *c->extent;
  if (c->world_from_object) me.world_from_object = *c->world_from_object;
  if (c->visible) me.visible = *c->visible;
  // FACING turns it from the new place: drawn with the half-width no turn exceeds.
  const Eigen::Matrix3d unturned = me.world_from_object;
  Eigen::Vector3d half = me.world_from_object.cwiseAbs() * (0.5 * me.extent);
  if (o.facing) half.head<2>().setConstant(HorizontalRadius(unturned, me.extent));
  const std::string* broken = nullptr;  // the relation the last draw broke
  const PlannedTerrain ground = TerrainAt(plan, f);
  for (int attempt = 0;; ++attempt) {
    const Eigen::Vector3d p = DrawPlace(ground, o, half, rng);
    c->position = p;
    if (o.facing) {
      me.world_from_object = FacingRotation(unturned, p, *o.facing);
      c->world_from_object = me.world_from_object;
    }
    broken = BrokenRelation(o, p, states);
    if (!broken && (o.overlap_allowed || !me.visible || !Collides(o, me, p, states))) return;
    if (attempt >= o.retries) break;
  }
  if (o.on_overlap == "delete" || o.on_overlap == "hide") {
    c->visible = false;  // a frame cannot delete it: it is hidden there
    return;
  }
  if (broken)
    rule.block.Fail("frame " + std::to_string(f.index) + ": cannot re-scatter " + o.name +
                    " satisfying " + *broken + " after " + std::to_string(o.retries) +
                    " retries; widen the relation or its space, or raise retries");
  rule.block.Fail("frame " + std::to_string(f.index) + ": cannot re-scatter " + o.name +
                  " without overlap after " + std::to_string(o.retries) +
                  " retries; lower the count, enlarge its space, or allow overlap in the scene "
                  "(overlap:true or on_overlap:delete)");
}

}  // namespace lsds
