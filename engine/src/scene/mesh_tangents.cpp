// Tangents by the MikkTSpace algorithm (facet/mesh.hpp says what it computes), written from
// Mikkelsen's description ("Simulation of Wrinkled Surfaces Revisited", 2008) and the conventions
// glTF adopted from it: the face tangent is unit(dP/du) (computed as sign(A) unit(A dP/du), A the
// uv area, which needs no division), its orientation sign(A); each corner projects it
// into the plane of its vertex normal, and a vertex sums its corners' directions weighted by the
// corner angle (measured between the corner's edges projected into the same plane). In double.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "facet/mesh.hpp"

namespace facet {
namespace {

using V = Eigen::Vector3d;

V unit_or_zero(const V& v) {
  const double len = v.norm();
  return len > 1e-30 && std::isfinite(len) ? V(v / len) : V::Zero();
}

// v with its component along unit n removed (n zero: v as it is).
V in_plane(const V& v, const V& n) { return v - n * n.dot(v); }

// A direction perpendicular to n (n zero: +x).
V any_perpendicular(const V& n) {
  if (n.isZero()) return V::UnitX();
  const V a = std::abs(n.x()) <= std::abs(n.y()) && std::abs(n.x()) <= std::abs(n.z()) ? V::UnitX()
              : std::abs(n.y()) <= std::abs(n.z())                                     ? V::UnitY()
                                                                                        : V::UnitZ();
  return unit_or_zero(a - n * n.dot(a));
}

}  // namespace

Status generate_tangents(Mesh& mesh, std::vector<std::uint32_t>* origin) {
  const std::size_t n = mesh.vertex_count();
  if (mesh.uvs.size() != n || mesh.normals.size() != n) {
    return {ErrorCode::invalid_argument, "uvs", "uvs: tangents need one texture coordinate and one normal per vertex"};
  }
  try {
    const std::size_t t_count = mesh.triangle_count();
    // Per triangle: the face tangent unit(dP/du) (zero when degenerate), and its orientation
    // (true: the uv area is positive, w = +1).
    std::vector<V> face(t_count);
    std::vector<char> preserving(t_count, 1);
    for (std::size_t f = 0; f < t_count; ++f) {
      const auto& tri = mesh.triangles[f];
      const V p0 = mesh.positions[tri[0]].cast<double>(), p1 = mesh.positions[tri[1]].cast<double>();
      const V p2 = mesh.positions[tri[2]].cast<double>();
      const Eigen::Vector2d t0 = mesh.uvs[tri[0]].cast<double>(), t1 = mesh.uvs[tri[1]].cast<double>();
      const Eigen::Vector2d t2 = mesh.uvs[tri[2]].cast<double>();
      const V d1 = p1 - p0, d2 = p2 - p0;
      const Eigen::Vector2d s1 = t1 - t0, s2 = t2 - t0;
      const double area = s1.x() * s2.y() - s1.y() * s2.x();
      preserving[f] = area > 0.0;
      const V os = s2.y() * d1 - s1.y() * d2;
      face[f] = area != 0.0 && std::isfinite(area) ? V((area > 0.0 ? 1.0 : -1.0) * unit_or_zero(os)) : V::Zero();
    }
    // Vertices whose corners have both orientations: the negative ones move to a copy.
    std::vector<char> has_pos(n, 0), has_neg(n, 0);
    for (std::size_t f = 0; f < t_count; ++f) {
      if (face[f].isZero()) continue;  // degenerate: no orientation to keep apart
      for (const std::uint32_t v : mesh.triangles[f]) (preserving[f] ? has_pos : has_neg)[v] = 1;
    }
    std::vector<std::uint32_t> twin(n, UINT32_MAX);
    for (std::size_t v = 0; v < n; ++v) {
      if (!(has_pos[v] && has_neg[v])) continue;
      if (mesh.positions.size() >= std::size_t{UINT32_MAX}) {
        return {ErrorCode::invalid_argument, "positions", "positions: splitting mirrored seams exceeds 32-bit indices"};
      }
      twin[v] = static_cast<std::uint32_t>(mesh.positions.size());
      if (origin) origin->push_back(std::uint32_t((*origin)[v]));
      mesh.positions.push_back(mesh.positions[v]);
      mesh.normals.push_back(mesh.normals[v]);
      mesh.uvs.push_back(mesh.uvs[v]);
      if (!mesh.colors.empty()) mesh.colors.push_back(mesh.colors[v]);
      if (!mesh.lightmap_uvs.empty()) mesh.lightmap_uvs.push_back(mesh.lightmap_uvs[v]);
    }
    for (std::size_t f = 0; f < t_count; ++f) {
      if (preserving[f] || face[f].isZero()) continue;
      for (std::uint32_t& v : mesh.triangles[f])
        if (twin[v] != UINT32_MAX) v = twin[v];
    }
    // Per vertex: the corners' projected face tangents, weighted by the corner angle.
    const std::size_t total = mesh.positions.size();
    std::vector<V> sum(total, V::Zero());
    std::vector<signed char> sign(total, 0);
    for (std::size_t f = 0; f < t_count; ++f) {
      if (face[f].isZero()) continue;
      const auto& tri = mesh.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = tri[k];
        const V nrm = unit_or_zero(mesh.normals[v].cast<double>());
        const V p = mesh.positions[v].cast<double>();
        const V a = unit_or_zero(in_plane(mesh.positions[tri[(k + 1) % 3]].cast<double>() - p, nrm));
        const V b = unit_or_zero(in_plane(mesh.positions[tri[(k + 2) % 3]].cast<double>() - p, nrm));
        const double c = std::clamp(a.dot(b), -1.0, 1.0);
        sum[v] += std::acos(c) * unit_or_zero(in_plane(face[f], nrm));
        sign[v] = preserving[f] ? 1 : -1;
      }
    }
    mesh.tangents.resize(total);
    for (std::size_t v = 0; v < total; ++v) {
      V t = unit_or_zero(sum[v]);
      if (t.isZero()) t = any_perpendicular(unit_or_zero(mesh.normals[v].cast<double>()));
      mesh.tangents[v] = Vec4(static_cast<float>(t.x()), static_cast<float>(t.y()), static_cast<float>(t.z()),
                              sign[v] < 0 ? -1.0f : 1.0f);
    }
    return {};
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "tangents", "tangents: out of memory"};
  }
}

}  // namespace facet
