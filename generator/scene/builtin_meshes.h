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

#include "generator/scene/mesh.h"

namespace lsds::gen {

TriangleMesh CarMesh();                 // 4.2 x 1.8 x 1.5 m: body, tapered cabin, windows, 4 wheels
TriangleMesh TruckMesh();               // 8 x 2.5 x 3.2 m: cab, cargo box, chassis, 6 wheels
TriangleMesh HumanMesh(uint64_t seed);  // 0.5 x 0.3 x 1.8 m; the walking pose varies per seed
TriangleMesh TreeMesh(uint64_t seed);   // a bracketed L-system: trunk/branch cylinders, foliage
TriangleMesh RockMesh(uint64_t seed);   // a noise-displaced icosphere
TriangleMesh CrateMesh();               // a box with proud edge battens
TriangleMesh BarrelMesh();              // a bulged drum with two hoops

}  // namespace lsds::gen
