// The world state of one frame: the plan's objects with that frame's changes
// applied, each with the transform and material it is rendered with. Frames are
// independent (a change lists what is in effect on its frame), which is what
// makes --frames and --shard give byte-identical results.
#pragma once

#include <string>
#include <vector>

#include "generator/plan/plan.h"
#include "libs/geometry/oriented_box.h"

namespace lsds::gen {

struct ObjectState {
  const PlannedObject* planned = nullptr;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d world_from_object = Eigen::Matrix3d::Identity();
  Eigen::Vector3d extent = Eigen::Vector3d::Ones();
  std::string material;
  bool visible = true;
  std::string asset;      // the class shape drawn (LCAP may swap it)
  uint32_t class_id = 0;  // in effect on the frame
  // World m/s: the path's velocity for an object moving along one, else 0
  // (discrete changes are jumps, not motion). Not part of the geometry.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();

  OrientedBox Box() const { return {position, extent / 2, world_from_object}; }
  // The world point of an object-frame point of the unit box.
  Eigen::Vector3d WorldFromUnit(const Eigen::Vector3d& p) const {
    return world_from_object * extent.cwiseProduct(p) + position;
  }
  Eigen::Vector3d UnitFromWorld(const Eigen::Vector3d& p) const {
    return (world_from_object.transpose() * (p - position)).cwiseQuotient(extent.cwiseMax(1e-12));
  }
  bool operator==(const ObjectState& o) const {
    return planned == o.planned && position == o.position &&
           world_from_object == o.world_from_object && extent == o.extent &&
           material == o.material && visible == o.visible && asset == o.asset &&
           class_id == o.class_id;
  }
};

struct WorldState {
  std::vector<ObjectState> objects;  // same order as Plan::objects
  std::string terrain_material;      // in effect on the frame
  PlannedTerrain terrain;            // its shape in effect on the frame (LCAP may change it)
  // Whether `o`'s terrain has the same surface (the same ground mesh).
  bool SameGround(const WorldState& o) const {
    return terrain.present == o.terrain.present && terrain.size == o.terrain.size &&
           terrain.perlin_amplitude == o.terrain.perlin_amplitude &&
           terrain.perlin_frequency == o.terrain.perlin_frequency &&
           terrain.perlin_seed == o.terrain.perlin_seed &&
           terrain.vegetation == o.terrain.vegetation;
  }
  bool operator==(const WorldState& o) const {
    return objects == o.objects && terrain_material == o.terrain_material && SameGround(o);
  }
};

// Throws lsds::Error naming the frame when a change refers to an unknown
// object.
WorldState WorldAt(const Plan& plan, const PlannedFrame& frame);

}  // namespace lsds::gen
