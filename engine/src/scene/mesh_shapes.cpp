// Procedural shapes. All are built by one parametric-grid routine: a (nu+1) x (nv+1) lattice whose
// quads (u,v) (u+1,v) (u+1,v+1) (u,v+1) wind counter-clockwise seen from the side the normal points
// to. Triangles with two coincident corners (sphere poles) are skipped. Normals come from the model
// (exact sphere and torus normals, flat cube faces), never from averaging. Texture coordinates:
// sphere u = longitude / 360 deg (from +x, counter-clockwise seen from +y), v = 1 at the north pole
// to 0 at the south pole; cube 0..1 across each face; plane 0..1 along x and along -z; torus
// u around the y axis and v around the tube, each 0..1. Seams have two vertices (u = 0 and 1).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "facet/mesh.hpp"

namespace facet {
namespace {

constexpr int kMaxTessellation = 4096;
constexpr float kPi = std::numbers::pi_v<float>;

int clamp_tessellation(int value, int minimum) { return std::clamp(value, minimum, kMaxTessellation); }

// fn(u, v) -> std::pair<Vec3 position, Vec3 normal> for u in [0, nu], v in [0, nv]; uv(u, v) the
// vertex's texture coordinates.
template <class Fn, class Uv>
void add_grid(Mesh& mesh, int nu, int nv, Fn fn, Uv uv) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (int u = 0; u <= nu; ++u) {
    for (int v = 0; v <= nv; ++v) {
      auto [p, n] = fn(u, v);
      mesh.positions.push_back(p);
      mesh.normals.push_back(n);
      mesh.uvs.push_back(uv(u, v));
    }
  }
  auto at = [&](int u, int v) { return base + static_cast<std::uint32_t>(u * (nv + 1) + v); };
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const auto& P = mesh.positions;
    if (P[a] == P[b] || P[b] == P[c] || P[a] == P[c]) return;
    mesh.triangles.push_back({a, b, c});
  };
  for (int u = 0; u < nu; ++u) {
    for (int v = 0; v < nv; ++v) {
      add(at(u, v), at(u + 1, v), at(u + 1, v + 1));
      add(at(u, v), at(u + 1, v + 1), at(u, v + 1));
    }
  }
}

float fraction(int i, int n) { return static_cast<float>(i) / static_cast<float>(n); }

// A flat rectangle from `origin` spanning `edge_u` and `edge_v`; its normal is unit(edge_u x edge_v).
// Texture coordinates run 0..1 along each edge.
void add_flat_patch(Mesh& mesh, const Vec3& origin, const Vec3& edge_u, const Vec3& edge_v, int n) {
  const Vec3 normal = edge_u.cross(edge_v).normalized();
  add_grid(
      mesh, n, n,
      [&](int u, int v) {
        return std::pair<Vec3, Vec3>{origin + fraction(u, n) * edge_u + fraction(v, n) * edge_v, normal};
      },
      [&](int u, int v) { return Vec2(fraction(u, n), fraction(v, n)); });
}

}  // namespace

Mesh make_uv_sphere(float radius, int segments, int rings) {
  segments = clamp_tessellation(segments, 3);
  rings = clamp_tessellation(rings, 2);
  Mesh mesh;
  // u runs from the north pole (phi = 0) to the south pole, v around the y axis.
  add_grid(mesh, rings, segments, [&](int u, int v) {
    const float phi = kPi * static_cast<float>(u) / static_cast<float>(rings);
    const float theta = 2.0f * kPi * static_cast<float>(v % segments) / static_cast<float>(segments);
    // Exact poles (sin(pi) in float is -8.7e-8, not 0); v % segments closes the seam exactly.
    const float sin_phi = (u == 0 || u == rings) ? 0.0f : std::sin(phi);
    const float cos_phi = u == 0 ? 1.0f : (u == rings ? -1.0f : std::cos(phi));
    const Vec3 n(sin_phi * std::cos(theta), cos_phi, -sin_phi * std::sin(theta));
    return std::pair<Vec3, Vec3>{radius * n, n};
  }, [&](int u, int v) { return Vec2(fraction(v, segments), 1.0f - fraction(u, rings)); });
  return mesh;
}

Mesh make_cube(float size, int subdivisions) {
  subdivisions = clamp_tessellation(subdivisions, 1);
  const float h = 0.5f * size;
  Mesh mesh;
  struct Face { Vec3 normal, u, v; };
  const Face faces[] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
  };
  for (const Face& f : faces) {
    add_flat_patch(mesh, h * (f.normal - f.u - f.v), size * f.u, size * f.v, subdivisions);
  }
  return mesh;
}

Mesh make_plane(float size_x, float size_z, int subdivisions) {
  subdivisions = clamp_tessellation(subdivisions, 1);
  Mesh mesh;
  add_flat_patch(mesh, Vec3(-0.5f * size_x, 0.0f, 0.5f * size_z), Vec3(size_x, 0, 0), Vec3(0, 0, -size_z),
                 subdivisions);
  return mesh;
}

Mesh make_disc(float radius, int segments) {
  segments = clamp_tessellation(segments, 3);
  Mesh mesh;
  // u = 0 the centre, u = 1 the rim (the centre's copies make one triangle per segment).
  add_grid(mesh, 1, segments, [&](int u, int v) {
    const float theta = 2.0f * kPi * static_cast<float>(v % segments) / static_cast<float>(segments);
    const float r = u == 0 ? 0.0f : radius;
    return std::pair<Vec3, Vec3>{Vec3(r * std::cos(theta), 0.0f, -r * std::sin(theta)), Vec3(0, 1, 0)};
  }, [&](int u, int v) {
    const float theta = 2.0f * kPi * static_cast<float>(v % segments) / static_cast<float>(segments);
    return u == 0 ? Vec2(0.5f, 0.5f) : Vec2(0.5f + 0.5f * std::cos(theta), 0.5f + 0.5f * std::sin(theta));
  });
  return mesh;
}

Mesh make_torus(float major_radius, float minor_radius, int segments, int sides) {
  segments = clamp_tessellation(segments, 3);
  sides = clamp_tessellation(sides, 3);
  Mesh mesh;
  // u runs around the y axis, v around the tube.
  add_grid(mesh, segments, sides, [&](int u, int v) {
    const float theta = 2.0f * kPi * static_cast<float>(u % segments) / static_cast<float>(segments);
    const float phi = 2.0f * kPi * static_cast<float>(v % sides) / static_cast<float>(sides);
    const Vec3 n(std::cos(phi) * std::cos(theta), std::sin(phi), -std::cos(phi) * std::sin(theta));
    const Vec3 centre(major_radius * std::cos(theta), 0.0f, -major_radius * std::sin(theta));
    return std::pair<Vec3, Vec3>{centre + minor_radius * n, n};
  }, [&](int u, int v) { return Vec2(fraction(u, segments), fraction(v, sides)); });
  return mesh;
}

}  // namespace facet
