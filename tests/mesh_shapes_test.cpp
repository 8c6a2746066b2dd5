// Procedural shapes: valid, outward winding that agrees with the normals, closed where they should
// be, and the right size (volumes by the divergence theorem, against the analytic values).
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "test_support.hpp"

namespace facet {
namespace {

constexpr double kPi = std::numbers::pi;

double enclosed_volume(const Mesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d a = m.positions[t[0]].cast<double>(), b = m.positions[t[1]].cast<double>(),
                          c = m.positions[t[2]].cast<double>();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

// Every directed edge (between welded positions) is matched by exactly one opposite edge.
bool is_closed_and_consistently_wound(const Mesh& m) {
  using Key = std::tuple<float, float, float>;
  std::map<Key, int> id;
  auto weld = [&](std::uint32_t i) {
    const Vec3& p = m.positions[i];
    return id.try_emplace(Key{p.x(), p.y(), p.z()}, static_cast<int>(id.size())).first->second;
  };
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{weld(t[k]), weld(t[(k + 1) % 3])}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    auto it = directed.find({edge.second, edge.first});
    if (it == directed.end() || it->second != 1) return false;
  }
  return true;
}

void expect_winding_matches_normals(const Mesh& m) {
  ASSERT_TRUE(validate_mesh(m).ok());
  ASSERT_GT(m.triangle_count(), 0u);
  for (const auto& n : m.normals) ASSERT_NEAR(n.norm(), 1.0f, 1e-5f);
  for (const auto& t : m.triangles) {
    const Vec3 face = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    ASSERT_GT(face.norm(), 0.0f);
    for (auto i : t) ASSERT_GT(face.normalized().dot(m.normals[i]), 0.0f) << "triangle wound against its normals";
  }
}

// Texture coordinates: one per vertex, in [0, 1], and no triangle flipped or collapsed in uv space
// except where the mapping must degenerate (the sphere's poles, where the whole top row meets).
void expect_uv_mapped(const Mesh& m, bool poles) {
  ASSERT_EQ(m.uvs.size(), m.vertex_count());
  for (const Vec2& uv : m.uvs) ASSERT_TRUE(uv.minCoeff() >= 0.0f && uv.maxCoeff() <= 1.0f) << uv.transpose();
  double area = 0;
  for (const auto& t : m.triangles) {
    const Vec2 a = m.uvs[t[0]], b = m.uvs[t[1]], c = m.uvs[t[2]];
    const double cross = double(b.x() - a.x()) * (c.y() - a.y()) - double(b.y() - a.y()) * (c.x() - a.x());
    area += std::abs(cross) / 2;
    if (!poles) {
      ASSERT_NE(cross, 0.0);
    }
  }
  (void)area;
}

TEST(MeshShapes, TextureCoordinates) {
  const Mesh sphere = make_uv_sphere(1, 8, 4);
  expect_uv_mapped(sphere, true);
  // The seam: u = 0 and u = 1 at the same position (+x); v = 1 at the north pole.
  bool seam0 = false, seam1 = false;
  for (std::size_t i = 0; i < sphere.vertex_count(); ++i) {
    if (sphere.positions[i] == Vec3(0, 1, 0)) {
      EXPECT_EQ(sphere.uvs[i].y(), 1.0f);
    }
    if (sphere.positions[i].isApprox(Vec3(std::sqrt(0.5f), std::sqrt(0.5f), 0))) {
      seam0 |= sphere.uvs[i].x() == 0.0f;
      seam1 |= sphere.uvs[i].x() == 1.0f;
    }
    // Longitude: u = atan2(-z, x) / 2 pi away from the poles and the seam.
    const Vec3& p = sphere.positions[i];
    if (std::abs(p.y()) < 0.99f && sphere.uvs[i].x() > 0.0f && sphere.uvs[i].x() < 1.0f) {
      double lon = std::atan2(-p.z(), p.x()) / (2 * kPi);
      if (lon < 0) lon += 1;
      EXPECT_NEAR(sphere.uvs[i].x(), lon, 1e-6);
      EXPECT_NEAR(sphere.uvs[i].y(), 1.0 - std::acos(std::clamp(double(p.y()), -1.0, 1.0)) / kPi, 1e-6);
    }
  }
  EXPECT_TRUE(seam0 && seam1);
  const Mesh cube = make_cube(2, 3);
  expect_uv_mapped(cube, false);
  // Each face covers the unit square: its area in uv is 1.
  double area = 0;
  for (const auto& t : cube.triangles) {
    const Vec2 a = cube.uvs[t[0]], b = cube.uvs[t[1]], c = cube.uvs[t[2]];
    area += (double(b.x() - a.x()) * (c.y() - a.y()) - double(b.y() - a.y()) * (c.x() - a.x())) / 2;
  }
  EXPECT_NEAR(area, 6.0, 1e-6);  // positive: uv winds as the faces do seen from outside
  const Mesh plane = make_plane(4, 2, 2);
  expect_uv_mapped(plane, false);
  for (std::size_t i = 0; i < plane.vertex_count(); ++i) {
    EXPECT_FLOAT_EQ(plane.uvs[i].x(), plane.positions[i].x() / 4 + 0.5f);
    EXPECT_FLOAT_EQ(plane.uvs[i].y(), 0.5f - plane.positions[i].z() / 2);
  }
  expect_uv_mapped(make_torus(1, 0.25f, 12, 6), false);
}

TEST(MeshShapes, SphereHasExactNormalsAndVolume) {
  const Mesh m = make_uv_sphere(2.0f, 64, 32);
  expect_winding_matches_normals(m);
  for (std::size_t i = 0; i < m.vertex_count(); ++i) {
    EXPECT_NEAR(m.positions[i].norm(), 2.0f, 1e-5f);
    EXPECT_LT((m.normals[i] - m.positions[i] / 2.0f).norm(), 1e-6f);
  }
  EXPECT_TRUE(is_closed_and_consistently_wound(m));
  const Mesh fine = make_uv_sphere(2.0f, 512, 256);
  EXPECT_NEAR(enclosed_volume(fine) / (4.0 / 3.0 * kPi * 8.0), 1.0, 1e-4);
  EXPECT_LT(enclosed_volume(m), enclosed_volume(fine));  // an inscribed polyhedron is smaller
}

TEST(MeshShapes, CubeHasFaceNormalsAndExactVolume) {
  const Mesh m = make_cube(3.0f, 4);
  expect_winding_matches_normals(m);
  EXPECT_EQ(m.vertex_count(), 6u * 25u);
  EXPECT_EQ(m.triangle_count(), 6u * 32u);
  for (std::size_t i = 0; i < m.vertex_count(); ++i) {
    // The normal is the axis on which the vertex sits on the surface.
    const Vec3& n = m.normals[i];
    EXPECT_FLOAT_EQ(m.positions[i].dot(n), 1.5f);
    EXPECT_FLOAT_EQ(n.cwiseAbs().sum(), 1.0f);
  }
  EXPECT_TRUE(is_closed_and_consistently_wound(m));
  EXPECT_NEAR(enclosed_volume(m), 27.0, 1e-4);
}

TEST(MeshShapes, PlaneFacesUp) {
  const Mesh m = make_plane(4.0f, 2.0f, 3);
  expect_winding_matches_normals(m);
  double area = 0;
  for (const auto& t : m.triangles) {
    const Vec3 c = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    EXPECT_GT(c.y(), 0.0f);
    area += 0.5 * c.norm();
  }
  EXPECT_NEAR(area, 8.0, 1e-5);
  for (const auto& n : m.normals) EXPECT_EQ(n, Vec3(0, 1, 0));
}

TEST(MeshShapes, TorusVolume) {
  const Mesh m = make_torus(2.0f, 0.5f, 48, 24);
  expect_winding_matches_normals(m);
  EXPECT_TRUE(is_closed_and_consistently_wound(m));
  const Mesh fine = make_torus(2.0f, 0.5f, 512, 256);
  // Inscribed polyhedra fall short by O(1/n^2): 1.25e-4 at 512 x 256.
  EXPECT_NEAR(enclosed_volume(fine) / (2.0 * kPi * kPi * 2.0 * 0.25), 1.0, 2e-4);
  EXPECT_LT(enclosed_volume(m), enclosed_volume(fine));
}

TEST(MeshShapes, TessellationIsClampedToValidMinimum) {
  const Mesh s = make_uv_sphere(1.0f, -5, 0);  // -> 3 segments, 2 rings
  expect_winding_matches_normals(s);
  EXPECT_TRUE(is_closed_and_consistently_wound(s));
  EXPECT_EQ(s.triangle_count(), 6u);
  expect_winding_matches_normals(make_cube(1.0f, 0));
  expect_winding_matches_normals(make_torus(1.0f, 0.3f, 1, 1));
}

}  // namespace
}  // namespace facet
