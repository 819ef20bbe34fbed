#include "generator/lang/capture/keep_placement.h"

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "generator/plan/terrain_height.h"
#include "libs/geometry/oriented_box.h"

namespace lsds {
namespace {

// An object as the frame's changes leave it.
struct State {
  const PlannedObject* planned = nullptr;
  Eigen::Vector3d position, extent;
  Eigen::Matrix3d world_from_object;
  bool visible = true, moved = false;
  const Rule* rule = nullptr;  // the last geometry change, for errors
};
using States = std::map<std::string, State>;

bool Lists(const std::vector<std::string>& symbols, const std::string& symbol) {
  return std::find(symbols.begin(), symbols.end(), symbol) != symbols.end();
}

States ApplyChanges(const Plan& plan,
                    const std::vector<const Rule*>& change_rules,
                    const PlannedFrame& f) {
  States states;
  for (const PlannedObject& o : plan.objects)
    states[o.name] = {&o, o.position, o.extent, o.world_from_object, o.visible, false, nullptr};
  for (size_t i = 0; i < f.changes.size(); ++i) {
    const ObjectChange& c = f.changes[i];
    State& s = states.at(c.object);
    if (c.visible) s.visible = *c.visible;
    if (!c.position && !c.extent && !c.world_from_object) continue;
    if (c.position) s.position = *c.position;
    if (c.extent) s.extent = *c.extent;
    if (c.world_from_object) s.world_from_object = *c.world_from_object;
    s.moved = true;
    s.rule = change_rules[i];
  }
  return states;
}

// Every object ON the terrain that no change moved stands on the frame's `ground` as it stood on
// the scene's: its z moves by the ground's rise under its centre.
void ReseatOnGround(const Plan& plan,
                    const PlannedTerrain& ground,
                    const Rule* ground_rule,
                    States* states,
                    PlannedFrame* f) {
  for (const PlannedObject& o : plan.objects) {
    State& s = states->at(o.name);
    if (s.moved || o.support != PlannedObject::Support::kTerrain) continue;
    const double rise = TerrainHeight(ground, s.position.x(), s.position.y()) -
                        TerrainHeight(plan.terrain, s.position.x(), s.position.y());
    s.position.z() += rise;
    s.moved = true;
    s.rule = ground_rule;
    ObjectChange seat;
    seat.object = o.name;
    seat.position = s.position;
    f->changes.push_back(seat);
  }
}

// Every moved object with a support is set back on it (an offset's z lifts it off on purpose).
void Reseat(const Plan& plan, const PlannedTerrain& ground, States* states, PlannedFrame* f) {
  for (auto& [name, s] : *states) {
    if (!s.moved) continue;
    const PlannedObject& o = *s.planned;
    const double half_z = (s.world_from_object.cwiseAbs() * (0.5 * s.extent)).z();
    double lift = 0;
    for (const auto& [key, v] : s.rule->block.Members())
      if (CanonicalKey(key) == "offset") lift = s.position.z() - o.position.z();
    if (o.support == PlannedObject::Support::kTerrain) {
      s.position.z() = TerrainHeight(ground, s.position.x(), s.position.y()) + half_z + lift;
    } else if (o.support == PlannedObject::Support::kTop) {
      s.position.z() = o.support_top + half_z + lift;
    } else {
      continue;  // no support: the change is taken as written
    }
    ObjectChange seat;
    seat.object = name;
    seat.position = s.position;
    f->changes.push_back(seat);
  }
}

// Objects standing ON (or placed IN) a moved object ride with it: the carrier's rigid displacement
// since the plan (translation and turn; its top's rise when it grew) is applied to each rider that
// has no geometry change of its own, in placement order so that a stack moves as one. The rider is
// the copy whose planned footprint holds the rider's planned centre. Each rider's new pose is
// appended as a change of the frame, with the carrier's velocity.
void CarryRiders(const Plan& plan, States* states, PlannedFrame* f) {
  std::map<std::string, Eigen::Vector3d> velocities;
  for (const ObjectChange& c : f->changes)
    if (c.velocity) velocities[c.object] = *c.velocity;
  for (const PlannedObject& rider : plan.objects) {
    State& r = states->at(rider.name);
    if (r.moved || rider.supports.empty()) continue;
    for (const PlannedObject& carrier : plan.objects) {
      if (&carrier == &rider || !Lists(rider.supports, carrier.symbol)) continue;
      const Eigen::Vector3d half = carrier.world_from_object.cwiseAbs() * (0.5 * carrier.extent);
      const Eigen::Vector3d d = (rider.position - carrier.position).cwiseAbs();
      if (d.x() > half.x() + 1e-9 || d.y() > half.y() + 1e-9) continue;  // not this copy
      const State& c = states->at(carrier.name);
      if (!c.moved) break;
      const Eigen::Matrix3d turn = c.world_from_object * carrier.world_from_object.transpose();
      const double rise = (c.world_from_object.cwiseAbs() * (0.5 * c.extent)).z() - half.z();
      r.position =
          c.position + turn * (rider.position - carrier.position) + Eigen::Vector3d(0, 0, rise);
      r.world_from_object = turn * rider.world_from_object;
      r.moved = true;
      r.rule = c.rule;
      ObjectChange ride;
      ride.object = rider.name;
      ride.position = r.position;
      if (!turn.isIdentity(1e-12)) ride.world_from_object = r.world_from_object;
      const auto v = velocities.find(carrier.name);
      if (v != velocities.end()) {
        ride.velocity = v->second;
        velocities[rider.name] = v->second;
      }
      f->changes.push_back(ride);
      break;
    }
  }
}

// A moved object that may not overlap must not overlap another visible one (but its supports and
// what stands on it, which touch it).
void CheckOverlaps(const States& states, const PlannedFrame& f) {
  for (const auto& [name, s] : states) {
    if (!s.moved || !s.visible || s.planned->overlap_allowed) continue;
    const OrientedBox mine{s.position, 0.5 * s.extent, s.world_from_object};
    for (const auto& [other_name, t] : states) {
      if (other_name == name || !t.visible) continue;
      if (Lists(s.planned->supports, t.planned->symbol)) continue;
      if (Lists(t.planned->supports, s.planned->symbol)) continue;
      const OrientedBox theirs{t.position, 0.5 * t.extent, t.world_from_object};
      if (mine.Intersects(theirs))
        s.rule->block.Fail("frame " + std::to_string(f.index) + ": this change makes " + name +
                           " overlap " + other_name +
                           ", which its LSCENE placement forbids; change less, or allow overlap "
                           "in the scene (overlap:true or on_overlap:allow)");
    }
  }
}

}  // namespace

void KeepPlacement(const Plan& plan,
                   const std::vector<const Rule*>& change_rules,
                   PlannedFrame* f,
                   const Rule* ground_rule) {
  States states = ApplyChanges(plan, change_rules, *f);
  const PlannedTerrain ground = TerrainAt(plan, *f);
  Reseat(plan, ground, &states, f);
  if (ground_rule != nullptr) ReseatOnGround(plan, ground, ground_rule, &states, f);
  // Riders follow their carriers' final (re-seated) poses.
  CarryRiders(plan, &states, f);
  CheckOverlaps(states, *f);
}

}  // namespace lsds
