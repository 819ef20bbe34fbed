// Ground vegetation (LSCENE `terrain{vegetation:{density, kind, height}}`; docs/generator.md,
// "Ground vegetation"): one prototype plant mesh per kind and a deterministic scatter of it over
// the terrain, each plant a transform of the prototype, baked into one world-space mesh that the
// renderer (generator/render/embree_scene.h) and the scene export (generator/scene_export/) both
// use. Plants are part of the terrain: its class and instance ids, its truth layers.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "generator/plan/plan.h"
#include "generator/scene/mesh.h"

namespace lsds::gen {

// A plant: the prototype (unit height, base at z = 0, top at z = 1 on its axis) scaled,
// turned about z and set on the terrain: point_in_world = linear * p + offset.
struct PlantInstance {
  Eigen::Matrix3f linear;
  Eigen::Vector3f offset;
};

// The prototype of `kind` (grass: a tuft of bent blades; plants: leaves round a stem under a
// flat top rosette, whose centre is the plant's top), in the vegetation material's colour.
TriangleMesh PlantPrototype(const std::string& kind);

// The most plants a scene may scatter (density x terrain area); more is a located error at
// planning time and an error here.
inline constexpr size_t kMaxPlants = 250000;
// How many plants a terrain scatters (0 without vegetation).
size_t PlantCount(const PlannedTerrain& terrain);

// The plants of a terrain: a jittered grid of cells 1/sqrt(density) m on a side over the terrain
// rectangle, one plant per cell at a uniform position within it (cells past the edge drop theirs),
// turned uniformly about z and sized x0.7-1.3 of the mean height, its base 1 cm below the terrain
// height there (no plant floats over the meshed ground). Every draw is counter_rng of the
// vegetation's seed and the cell, so the same plan scatters the same plants everywhere.
std::vector<PlantInstance> ScatterVegetation(const PlannedTerrain& terrain);

// Every plant of the scatter in world coordinates: the prototype placed by each transform, in
// the scatter's order (empty without vegetation).
TriangleMesh VegetationMesh(const PlannedTerrain& terrain);

// The material plants are shaded with (materials.h): foliage.
inline constexpr const char* kVegetationMaterial = "foliage";

// The depth of the plant's base below the terrain height.
inline constexpr float kPlantSinkM = 0.01f;

}  // namespace lsds::gen
