#include "generator/scene/world.h"

#include "libs/util/error.h"

namespace lsds::gen {

WorldState WorldAt(const Plan& plan, const PlannedFrame& frame) {
  WorldState world;
  world.terrain_material = EnvironmentAt(plan, frame).terrain_material;
  world.terrain = TerrainAt(plan, frame);
  world.objects.reserve(plan.objects.size());
  for (const PlannedObject& o : plan.objects) {
    ObjectState s;
    s.planned = &o;
    s.position = o.position;
    s.world_from_object = o.world_from_object;
    s.extent = o.extent;
    s.material = o.material;
    s.visible = o.visible;
    s.asset = o.class_name;
    s.class_id = o.class_id;
    world.objects.push_back(s);
  }
  for (const ObjectChange& change : frame.changes) {
    ObjectState* target = nullptr;
    for (ObjectState& s : world.objects) {
      if (s.planned->name == change.object) target = &s;
    }
    if (target == nullptr) {
      throw Error("frame " + std::to_string(frame.index) + ": a change refers to unknown object '" +
                  change.object + "'");
    }
    if (change.position) target->position = *change.position;
    if (change.world_from_object) target->world_from_object = *change.world_from_object;
    if (change.extent) target->extent = *change.extent;
    if (change.material) target->material = *change.material;
    if (change.visible) target->visible = *change.visible;
    if (change.asset) target->asset = *change.asset;
    if (change.class_id) target->class_id = *change.class_id;
    if (change.velocity) target->velocity = *change.velocity;
  }
  return world;
}

}  // namespace lsds::gen
