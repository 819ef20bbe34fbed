#include "generator/scene/smooth_normals.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <Eigen/Geometry>

namespace lsds::gen {
namespace {

// A key for welding: positions rounded to a millionth of the mesh's size.
struct Quantized {
  int64_t x, y, z;
  bool operator==(const Quantized& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct QuantizedHash {
  size_t operator()(const Quantized& q) const {
    return std::hash<int64_t>()(q.x * 73856093 ^ q.y * 19349663 ^ q.z * 83492791);
  }
};

}  // namespace

std::vector<Eigen::Vector3f> CreaseCornerNormals(const TriangleMesh& mesh, double crease_deg) {
  const size_t nt = mesh.triangles.size();
  std::vector<Eigen::Vector3f> face(nt);  // area-weighted (length = 2 * area)
  for (size_t t = 0; t < nt; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    face[t] = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                  .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
  }
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const Eigen::Vector3f& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double scale = 1e6 / std::max(1e-12f, (hi - lo).maxCoeff());
  std::unordered_map<Quantized, int, QuantizedHash> weld;
  std::vector<int> group(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const Eigen::Vector3f& p = mesh.positions[v];
    const Quantized q{std::llround((p.x() - lo.x()) * scale),
                      std::llround((p.y() - lo.y()) * scale),
                      std::llround((p.z() - lo.z()) * scale)};
    group[v] = weld.emplace(q, static_cast<int>(weld.size())).first->second;
  }
  // Faces around each welded vertex (CSR).
  std::vector<int> start(weld.size() + 1, 0);
  for (const Eigen::Vector3i& tri : mesh.triangles)
    for (int c = 0; c < 3; ++c) ++start[group[tri[c]] + 1];
  for (size_t g = 0; g < weld.size(); ++g) start[g + 1] += start[g];
  std::vector<int> faces(start.back()), fill(start.begin(), start.end() - 1);
  for (size_t t = 0; t < nt; ++t)
    for (int c = 0; c < 3; ++c) faces[fill[group[mesh.triangles[t][c]]]++] = static_cast<int>(t);

  const float cos_crease = static_cast<float>(std::cos(crease_deg * M_PI / 180));
  std::vector<Eigen::Vector3f> out(3 * nt);
  for (size_t t = 0; t < nt; ++t) {
    const float own_len = face[t].norm();
    // A degenerate face (a pole of a sphere) takes every neighbour.
    const Eigen::Vector3f own =
        own_len > 0 ? Eigen::Vector3f(face[t] / own_len) : Eigen::Vector3f::Zero();
    for (int c = 0; c < 3; ++c) {
      const int g = group[mesh.triangles[t][c]];
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (int k = start[g]; k < start[g + 1]; ++k) {
        const Eigen::Vector3f& f = face[faces[k]];
        const float len = f.norm();
        if (len > 0 && (own_len == 0 || f.dot(own) >= cos_crease * len)) sum += f;
      }
      const float n = sum.norm();
      out[3 * t + c] = n > 0 ? Eigen::Vector3f(sum / n) : own;
    }
  }
  return out;
}

std::vector<Eigen::Vector3f> HeightfieldCornerNormals(
    const TriangleMesh& mesh, const std::function<double(double, double)>& height, double step) {
  std::vector<Eigen::Vector3f> at_vertex(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const double x = mesh.positions[v].x(), y = mesh.positions[v].y();
    const double dx = (height(x + step, y) - height(x - step, y)) / (2 * step);
    const double dy = (height(x, y + step) - height(x, y - step)) / (2 * step);
    at_vertex[v] = Eigen::Vector3d(-dx, -dy, 1).normalized().cast<float>();
  }
  std::vector<Eigen::Vector3f> out(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) out[3 * t + c] = at_vertex[mesh.triangles[t][c]];
  return out;
}

}  // namespace lsds::gen
