// The procedural meshes of the built-in UAV classes (vehicles, a posed human
// figure, L-system trees, rocks, crates, barrels), in metres with z up and
// the object's front along +x. Each is normalized to the unit box by the
// object library (object_library.h), so a plan's `extent` is its exact size.
// Parts that are not the object's material (tyres, windows, skin, bark) carry
// a constant-colour map (TriangleMesh::albedo_maps), so that a car painted
// red keeps black tyres; the material's albedo colours the rest.
// Deterministic: the same seed gives the same mesh on every machine.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/scene/mesh.h"

namespace lsds::gen {

// The car family (docs/generator.md, "Built-in classes"): each shape has its own
// size in metres, which is the mesh's exact bounds and the natural extent of a
// car drawn as it.
struct CarShape {
  const char* name;      // sedan, hatchback, suv, pickup, van
  Eigen::Vector3d size;  // length (x) x width (y) x height (z), metres
};
const std::vector<CarShape>& CarShapes();
// The shape a planner's draw `key` picks (uniform over the family).
size_t CarShapeOfKey(uint64_t key);
// The shape whose proportions (length : width : height, compared in log space)
// are nearest `extent`'s: what a car of that size draws. A car at its shape's
// own size draws that shape.
size_t CarShapeNearest(const Eigen::Vector3d& extent);
// Body on wheels (a dark tyre with a light rim on the outside), a tapered
// cabin with a dark window band; the pickup has an open bed, the van a tall box.
TriangleMesh CarMesh(size_t shape);
// A body paint from a realistic palette (white, black, grey and silver make up
// about four in five, then blue, red, beige, green): a material name
// (materials.h), drawn by counter_rng from `seed`.
const std::string& CarPaint(uint64_t seed);
// The palette: (material, share of cars), shares summing to 1.
const std::vector<std::pair<std::string, double>>& CarPaintPalette();

TriangleMesh TruckMesh();               // 8 x 2.5 x 3.2 m: cab, cargo box, chassis, 6 wheels
TriangleMesh HumanMesh(uint64_t seed);  // 0.5 x 0.3 x 1.8 m; the walking pose varies per seed
TriangleMesh TreeMesh(uint64_t seed);   // a bracketed L-system: trunk/branch cylinders, foliage
TriangleMesh RockMesh(uint64_t seed);   // a noise-displaced icosphere
TriangleMesh CrateMesh();               // a box with proud edge battens
TriangleMesh BarrelMesh();              // a bulged drum with two hoops

}  // namespace lsds::gen
