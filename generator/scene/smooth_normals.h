// Smooth shading normals: per-corner normals interpolated by the renderer so
// that curved surfaces show no triangle facets, while creases sharper than a
// threshold (a box's edges, a cylinder's rim) stay sharp.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "generator/scene/mesh.h"

namespace lsds::gen {

// Area-weighted vertex normals of the faces around each corner whose normal is
// within `crease_deg` of the corner's own face. Vertices at the same position
// (seams of procedural and loaded meshes) are welded for the average. Three
// unit normals per triangle, in the mesh's frame.
std::vector<Eigen::Vector3f> CreaseCornerNormals(const TriangleMesh& mesh, double crease_deg = 40);

// The normals of a heightfield z = height(x, y) at every corner, from central
// differences of `height` with step `step` (metres): continuous across
// triangle edges and across meshes that sample the same function.
std::vector<Eigen::Vector3f> HeightfieldCornerNormals(
    const TriangleMesh& mesh, const std::function<double(double, double)>& height, double step);

}  // namespace lsds::gen
