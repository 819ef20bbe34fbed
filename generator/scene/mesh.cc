#include "generator/scene/mesh.h"

#include <cmath>
#include <map>
#include <utility>

#include <Eigen/Dense>

namespace lsds::gen {

void TriangleMesh::Append(const TriangleMesh& other,
                          const Eigen::Matrix3f& linear,
                          const Eigen::Vector3f& offset) {
  corner_normals.clear();  // no longer matches the triangles
  const int base = static_cast<int>(positions.size());
  const size_t base_triangles = triangles.size();
  // Texture coordinates and maps follow their triangles; the side without
  // them gets (0, 0) and no map.
  if (!uvs.empty() || !other.uvs.empty()) {
    uvs.resize(positions.size(), Eigen::Vector2f::Zero());
    if (other.uvs.empty())
      uvs.resize(positions.size() + other.positions.size(), Eigen::Vector2f::Zero());
    else
      uvs.insert(uvs.end(), other.uvs.begin(), other.uvs.end());
  }
  if (!triangle_map.empty() || !other.triangle_map.empty()) {
    triangle_map.resize(base_triangles, -1);
    const int map_base = static_cast<int>(albedo_maps.size());
    for (size_t t = 0; t < other.triangles.size(); ++t) {
      const int m = t < other.triangle_map.size() ? other.triangle_map[t] : -1;
      triangle_map.push_back(m < 0 ? -1 : m + map_base);
    }
    albedo_maps.insert(albedo_maps.end(), other.albedo_maps.begin(), other.albedo_maps.end());
  }
  for (const Eigen::Vector3f& p : other.positions) positions.push_back(linear * p + offset);
  const bool flip = linear.determinant() < 0;
  for (const Eigen::Vector3i& t : other.triangles) {
    triangles.push_back(flip ? Eigen::Vector3i(t[0], t[2], t[1]) + Eigen::Vector3i::Constant(base)
                             : t + Eigen::Vector3i::Constant(base));
  }
}

TriangleMesh MakeBoxMesh() {
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.positions.emplace_back(
        (k & 1) ? 0.5f : -0.5f, (k & 2) ? 0.5f : -0.5f, (k & 4) ? 0.5f : -0.5f);
  }
  // Two triangles per face, wound outward.
  const int faces[6][4] = {
      {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    mesh.triangles.emplace_back(f[0], f[1], f[2]);
    mesh.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return mesh;
}

TriangleMesh MakeLatheMesh(int segments, int rings, double (*radius)(double t)) {
  TriangleMesh mesh;
  for (int r = 0; r <= rings; ++r) {
    const double t = static_cast<double>(r) / rings;
    const double rad = radius(t);
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * M_PI * s / segments;
      mesh.positions.emplace_back(static_cast<float>(rad * std::cos(a)),
                                  static_cast<float>(rad * std::sin(a)),
                                  static_cast<float>(t - 0.5));
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      mesh.triangles.emplace_back(a, b, d);
      mesh.triangles.emplace_back(a, d, c);
    }
  }
  for (int cap = 0; cap < 2; ++cap) {
    const double t = cap;
    if (radius(t) <= 0) continue;
    const int centre = static_cast<int>(mesh.positions.size());
    mesh.positions.emplace_back(0.f, 0.f, static_cast<float>(t - 0.5));
    const int ring = cap * rings * segments;
    for (int s = 0; s < segments; ++s) {
      const int a = ring + s, b = ring + (s + 1) % segments;
      if (cap == 0) {
        mesh.triangles.emplace_back(centre, b, a);
      } else {
        mesh.triangles.emplace_back(centre, a, b);
      }
    }
  }
  return mesh;
}

TriangleMesh MakeSphereMesh(int segments, int rings) {
  return MakeLatheMesh(segments, rings, [](double t) { return 0.5 * std::sin(M_PI * t); });
}

TriangleMesh MakeCylinderMesh(int segments) {
  return MakeLatheMesh(segments, 1, [](double) { return 0.5; });
}

TriangleMesh MakeConeMesh(int segments) {
  return MakeLatheMesh(segments, 1, [](double t) { return 0.5 * (1 - t); });
}

TriangleMesh MakeIcosphereMesh(int subdivisions) {
  TriangleMesh mesh;
  const float g = (1 + std::sqrt(5.f)) / 2;
  const float corners[12][3] = {{-1, g, 0},
                                {1, g, 0},
                                {-1, -g, 0},
                                {1, -g, 0},
                                {0, -1, g},
                                {0, 1, g},
                                {0, -1, -g},
                                {0, 1, -g},
                                {g, 0, -1},
                                {g, 0, 1},
                                {-g, 0, -1},
                                {-g, 0, 1}};
  for (const auto& c : corners)
    mesh.positions.push_back(0.5f * Eigen::Vector3f(c[0], c[1], c[2]).normalized());
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;  // each edge split once
    auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      const int index = static_cast<int>(mesh.positions.size());
      mesh.positions.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]).normalized());
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> finer;
    for (const Eigen::Vector3i& t : mesh.triangles) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      finer.insert(finer.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
    }
    mesh.triangles = std::move(finer);
  }
  return mesh;
}

TriangleMesh MakeTorusMesh(int segments, int sides, double minor_over_major) {
  TriangleMesh mesh;
  const double major = 1.0, minor = minor_over_major;
  for (int s = 0; s < segments; ++s) {
    const double a = 2 * M_PI * s / segments;
    for (int k = 0; k < sides; ++k) {
      const double b = 2 * M_PI * k / sides;
      const double r = major + minor * std::cos(b);
      mesh.positions.emplace_back(static_cast<float>(r * std::cos(a)),
                                  static_cast<float>(r * std::sin(a)),
                                  static_cast<float>(minor * std::sin(b)));
    }
  }
  for (int s = 0; s < segments; ++s) {
    for (int k = 0; k < sides; ++k) {
      const int s1 = (s + 1) % segments, k1 = (k + 1) % sides;
      const int a = s * sides + k, b = s1 * sides + k, c = s1 * sides + k1, d = s * sides + k1;
      mesh.triangles.emplace_back(a, b, c);
      mesh.triangles.emplace_back(a, c, d);
    }
  }
  return mesh;
}

void NormalizeToUnitBox(TriangleMesh* mesh) {
  if (mesh->positions.empty()) return;
  Eigen::Vector3f lo = mesh->positions[0], hi = lo;
  for (const Eigen::Vector3f& p : mesh->positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3f centre = 0.5f * (lo + hi);
  const Eigen::Vector3f size = hi - lo;
  for (Eigen::Vector3f& p : mesh->positions) {
    for (int a = 0; a < 3; ++a) {
      p[a] = size[a] > 0 ? (p[a] - centre[a]) / size[a] : 0.f;
    }
  }
}

}  // namespace lsds::gen
