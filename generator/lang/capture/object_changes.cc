#include "generator/lang/capture/object_changes.h"

#include <cmath>
#include <string>
#include <vector>

#include "generator/lang/asset_choice.h"
#include "generator/lang/capture/quota_draws.h"
#include "generator/lang/scene/class_catalog.h"
#include "generator/plan/terrain_height.h"

namespace lsds {
namespace {

// `class:` of a change: one of its options (the frame's class bin's, under importance sampling,
// when the swap can draw it: a name that resolves to one class, not a library selection of
// several), then one of the option's assets, uniformly, at its own size.
void DrawClass(const Node& v,
               const PlannedObject& o,
               Rng& rng,
               const FrameDemand* demand,
               ClassSwaps* swaps,
               ObjectChange* c) {
  std::string option = IsTagSelection(v) ? std::string("tags") : SampleString(v, rng);
  if (const auto bin = DemandedBin(demand, "class", &o); bin && !IsTagSelection(v)) {
    for (const std::string& candidate : StringOptions(v)) {
      const std::vector<SceneClass> resolved = swaps->Candidates(v, candidate);
      if (resolved.size() == 1 && swaps->Class(o.symbol, resolved[0]).second == bin->first)
        option = candidate;
    }
  }
  const std::vector<SceneClass> candidates = swaps->Candidates(v, option);
  const SceneClass& drawn = candidates.size() == 1
                                ? candidates[0]
                                : candidates[static_cast<size_t>(rng.UniformInt(
                                      0, static_cast<int64_t>(candidates.size()) - 1))];
  const auto [asset, id] = swaps->Class(o.symbol, drawn);
  c->asset = asset;
  c->class_id = id;
  // The drawn asset keeps its own proportions and size; its base stays on the support
  // (KeepPlacement re-seats it). An `extent` later in the block still wins.
  c->extent = swaps->NaturalExtent(drawn, v, rng.KeyHere(ClassCatalog::kMemberKeyPurpose));
}

// The vertical velocity of an object standing on the terrain: the slope along its motion, by a
// central difference of the terrain height.
double TerrainClimb(const PlannedTerrain& terrain,
                    const Eigen::Vector3d& p,
                    const Eigen::Vector3d& v) {
  const double e = 1e-3;
  const double dx =
      (TerrainHeight(terrain, p.x() + e, p.y()) - TerrainHeight(terrain, p.x() - e, p.y())) /
      (2 * e);
  const double dy =
      (TerrainHeight(terrain, p.x(), p.y() + e) - TerrainHeight(terrain, p.x(), p.y() - e)) /
      (2 * e);
  return dx * v.x() + dy * v.y();
}

}  // namespace

ObjectChange DrawObjectChange(const Rule& rule,
                              const PlannedObject& o,
                              Rng& rng,
                              const FrameDemand* demand,
                              ClassSwaps* swaps) {
  ObjectChange c;
  c.object = o.name;
  for (const auto& [key, v] : rule.block.Members()) {
    const std::string k = CanonicalKey(key);
    if (k == "material") c.material = SampleString(v, rng);
    if (k == "rotation") c.world_from_object = RotationFromEulerDeg(SampleVec3(v, rng));
    if (k == "visible" || k == "visibility") c.visible = SampleBool(v, rng);
    if (k == "extent") {
      c.extent = SampleVec3(v, rng);
      if (c.extent->minCoeff() <= 0) v.Fail("extent components must be > 0");
    }
    if (k == "scale") {
      const Eigen::Vector3d s = SampleScale(v, rng);
      if (s.minCoeff() <= 0) v.Fail("scale must be > 0");
      c.extent = o.extent.cwiseProduct(s);
    }
    if (k == "offset") c.position = o.position + SampleVec3(v, rng);
    if (k == "position") {
      if (v->is_object())
        v.Fail(
            "a position change is a point [x,y,z]; for a new place drawn by the object's "
            "LSCENE constraints write rescatter:true");
      c.position = SampleVec3(v, rng);
    }
    if (k == "class") DrawClass(v, o, rng, demand, swaps, &c);
  }
  return c;
}

void MoveAlongLegs(const Rule& rule,
                   const PlannedObject& o,
                   const Plan& plan,
                   const PlannedTerrain& ground,
                   int64_t k,
                   double fps,
                   ObjectChange* c) {
  const PlannedObject* first = &o;
  for (const PlannedObject& p : plan.objects)
    if (p.symbol == o.symbol) {
      first = &p;
      break;
    }
  double t = static_cast<double>(k - rule.when.begin) / fps;
  FlightSample at;
  bool moving = false;
  for (const Rule::Leg& leg : rule.legs) {
    const Flight& flight = leg.flight;
    const double lap = leg.track ? leg.track->Duration() : flight.length / flight.speed;
    if (t < lap * static_cast<double>(leg.repetitions)) {
      const double in_lap = t - std::floor(t / lap) * lap;
      at = leg.track ? leg.track->At(in_lap) : flight.At(in_lap * flight.speed);
      moving = true;
      break;
    }
    t -= lap * static_cast<double>(leg.repetitions);
    at = leg.track ? leg.track->At(lap) : flight.At(flight.length);
  }
  c->position = at.centre + (o.position - first->position);
  Eigen::Vector3d v = moving ? at.velocity : Eigen::Vector3d::Zero();
  if (o.support == PlannedObject::Support::kTerrain)
    v.z() = TerrainClimb(ground, *c->position, v);
  else if (o.support == PlannedObject::Support::kTop)
    v.z() = 0;
  c->velocity = v;
  // Heading: the yaw of travel on top of the object's rotation (the block's, else the planned
  // one).
  if (rule.heading && at.tangent.head<2>().norm() > 1e-12) {
    const double yaw = std::atan2(at.tangent.y(), at.tangent.x());
    c->world_from_object = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                           (c->world_from_object ? *c->world_from_object : o.world_from_object);
  }
}

}  // namespace lsds
