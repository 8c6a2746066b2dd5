// Crease-aware vertex normals (see compute_vertex_normals in facet/mesh.hpp for the contract).
//
// Per corner (triangle t, vertex v): sum over the non-degenerate faces g around v (positions welded
// by exact value) with angle(n_t, n_g) <= crease of corner_angle(g, v) * n_g. The weighted mean of
// unit vectors inside a cone of half-angle < 90 deg stays inside it, so every corner normal is
// within the crease angle of its own face: a 90 deg edge is never smoothed at the default 60 deg.
// Accumulation is in double; faces are visited in a fixed order, so equal sets give equal bits and
// corners that end with bit-identical normals share a vertex.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "facet/mesh.hpp"

namespace facet {
namespace {

using Vec3d = Eigen::Vector3d;

// Cosine tolerance so that faces that are coplanar up to rounding count as within a 0 deg crease.
constexpr double kCosTolerance = 1e-6;

struct PositionKey {
  std::uint32_t bits[3];
  bool operator==(const PositionKey&) const = default;
};

struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const noexcept {
    std::size_t h = 1469598103934665603ull;
    for (std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
    return h;
  }
};

PositionKey key_of(const Vec3& p) {
  PositionKey k{};
  for (int i = 0; i < 3; ++i) {
    const float c = p[i] == 0.0f ? 0.0f : p[i];  // -0 and +0 are the same place
    std::memcpy(&k.bits[i], &c, sizeof c);
  }
  return k;
}

// Welded id per vertex: vertices with bit-identical finite positions share an id.
std::vector<std::uint32_t> weld(const std::vector<Vec3>& positions) {
  std::vector<std::uint32_t> id(positions.size());
  std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> first;
  first.reserve(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const auto self = static_cast<std::uint32_t>(i);
    id[i] = positions[i].allFinite() ? first.try_emplace(key_of(positions[i]), self).first->second : self;
  }
  return id;
}

double corner_angle(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const Vec3d e1 = a - p, e2 = b - p;
  return std::atan2(e1.cross(e2).norm(), e1.dot(e2));
}

}  // namespace

void compute_vertex_normals(Mesh& mesh, float crease_angle_deg, std::vector<std::uint32_t>* origin) {
  const std::size_t vertex_count = mesh.positions.size();
  const std::size_t tri_count = mesh.triangles.size();
  const double cos_crease =
      std::cos(std::clamp(static_cast<double>(crease_angle_deg), 0.0, 180.0) * std::numbers::pi / 180.0) -
      kCosTolerance;

  // Face normals and corner weights (zero for degenerate or non-finite triangles).
  std::vector<Vec3d> face_normal(tri_count, Vec3d::Zero());
  std::vector<std::array<double, 3>> corner_weight(tri_count, {0.0, 0.0, 0.0});
  for (std::size_t t = 0; t < tri_count; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3d p[3] = {mesh.positions[tri[0]].cast<double>(), mesh.positions[tri[1]].cast<double>(),
                        mesh.positions[tri[2]].cast<double>()};
    const Vec3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double len = n.norm();
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    face_normal[t] = n / len;
    for (int k = 0; k < 3; ++k) corner_weight[t][k] = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
  }

  // Faces around each welded vertex, in triangle order (CSR).
  const std::vector<std::uint32_t> welded = weld(mesh.positions);
  std::vector<std::uint32_t> start(vertex_count + 1, 0);
  for (const auto& tri : mesh.triangles)
    for (std::uint32_t v : tri) ++start[welded[v] + 1];
  for (std::size_t i = 0; i < vertex_count; ++i) start[i + 1] += start[i];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  std::vector<std::uint32_t> corners(start.back());  // t * 3 + k
  for (std::size_t t = 0; t < tri_count; ++t)
    for (int k = 0; k < 3; ++k) corners[fill[welded[mesh.triangles[t][k]]]++] = static_cast<std::uint32_t>(3 * t + k);

  // Corner normals; then one output vertex per distinct normal of each original vertex.
  std::vector<Vec3> new_normals(vertex_count, Vec3::Zero());
  std::vector<bool> assigned(vertex_count, false);
  std::vector<std::vector<std::uint32_t>> extra_of(vertex_count);  // extra copies of a vertex, if split
  for (std::size_t t = 0; t < tri_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[t][k];
      const std::uint32_t w = welded[v];
      const Vec3d& own = face_normal[t];
      const bool own_valid = own.squaredNorm() > 0.0;
      Vec3d sum = Vec3d::Zero();
      for (std::uint32_t i = start[w]; i < start[w + 1]; ++i) {
        const std::uint32_t g = corners[i] / 3, gk = corners[i] % 3;
        if (corner_weight[g][gk] <= 0.0) continue;
        if (own_valid && face_normal[g].dot(own) < cos_crease) continue;
        sum += corner_weight[g][gk] * face_normal[g];
      }
      const double len = sum.norm();
      const Vec3 normal = len > 0.0 ? Vec3((sum / len).cast<float>()) : own.cast<float>();

      if (!assigned[v]) {
        assigned[v] = true;
        new_normals[v] = normal;
        continue;
      }
      if (new_normals[v] == normal) continue;
      std::uint32_t target = 0;
      bool found = false;
      for (std::uint32_t e : extra_of[v]) {
        if (new_normals[e] == normal) {
          target = e;
          found = true;
          break;
        }
      }
      if (!found) {
        target = static_cast<std::uint32_t>(mesh.positions.size());
        if (origin) origin->push_back(std::uint32_t((*origin)[v]));
        mesh.positions.push_back(mesh.positions[v]);
        if (!mesh.uvs.empty()) mesh.uvs.push_back(mesh.uvs[v]);
        if (!mesh.colors.empty()) mesh.colors.push_back(mesh.colors[v]);
        if (!mesh.lightmap_uvs.empty()) mesh.lightmap_uvs.push_back(mesh.lightmap_uvs[v]);
        new_normals.push_back(normal);
        extra_of[v].push_back(target);
      }
      mesh.triangles[t][k] = target;
    }
  }
  mesh.normals = std::move(new_normals);
}

}  // namespace facet
