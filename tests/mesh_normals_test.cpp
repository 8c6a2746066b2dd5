// Crease-aware vertex normals: hard edges stay hard, smooth surfaces come out smooth, weights are
// by corner angle, degenerate input stays finite.
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "test_support.hpp"

namespace facet {
namespace {

// A cube with 8 shared corners and 12 triangles (each face split on a diagonal), no normals.
Mesh shared_corner_cube() {
  const std::vector<float> p = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
  const std::vector<std::uint32_t> idx = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                          2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
  Mesh m;
  for (std::size_t i = 0; i < p.size(); i += 3) m.positions.emplace_back(p[i], p[i + 1], p[i + 2]);
  for (std::size_t i = 0; i < idx.size(); i += 3) m.triangles.push_back({idx[i], idx[i + 1], idx[i + 2]});
  m.normals.assign(m.positions.size(), Vec3::Zero());
  return m;
}

Vec3 face_normal(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
  return (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).normalized();
}

TEST(MeshNormals, CubeEdgesStayHard) {
  Mesh m = shared_corner_cube();
  compute_vertex_normals(m, 60.0f);
  EXPECT_EQ(m.vertex_count(), 24u);  // each corner split into its 3 faces
  ASSERT_TRUE(validate_mesh(m).ok());
  for (const auto& t : m.triangles) {
    const Vec3 f = face_normal(m, t);
    for (auto i : t) EXPECT_LT((m.normals[i] - f).norm(), 1e-6f);
  }
}

TEST(MeshNormals, AngleWeightingIgnoresHowFacesAreSplit) {
  // Crease 180: everything is smoothed. Depending on the diagonals, a corner touches one or two
  // triangles of each face, but every face spans 90 deg at the corner, so angle weights give
  // exactly the diagonal. (Uniform per-triangle weights would not.)
  Mesh m = shared_corner_cube();
  compute_vertex_normals(m, 180.0f);
  EXPECT_EQ(m.vertex_count(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    const Vec3 expected = m.positions[i].normalized();
    EXPECT_LT((m.normals[i] - expected).norm(), 1e-6f) << "corner " << i;
  }
}

TEST(MeshNormals, SmoothSurfaceIsSmoothAcrossUvSeams) {
  // A UV sphere has a seam of duplicated positions; welding must smooth across it.
  Mesh m = make_uv_sphere(1.0f, 48, 24);
  for (auto& n : m.normals) n = Vec3::Zero();
  const std::size_t before = m.vertex_count();
  compute_vertex_normals(m, 60.0f);
  EXPECT_EQ(m.vertex_count(), before);  // no split anywhere
  double worst = 0;
  std::vector<bool> used(m.vertex_count(), false);  // the seam copy of each pole is in no triangle
  for (const auto& t : m.triangles)
    for (auto i : t) used[i] = true;
  for (std::size_t i = 0; i < m.vertex_count(); ++i) {
    if (!used[i]) continue;
    worst = std::max(worst, std::acos(std::min(1.0, double(m.normals[i].dot(m.positions[i].normalized())))));
  }
  EXPECT_LT(worst * 180.0 / std::numbers::pi, 0.5) << "largest deviation from the true normal, degrees";
}

TEST(MeshNormals, DegenerateTrianglesStayFinite) {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(5, 5, 5)};
  m.triangles = {{0, 1, 2}, {0, 1, 3}, {4, 4, 4}};  // a good one, a collinear one, a point
  m.normals.assign(5, Vec3::Zero());
  compute_vertex_normals(m, 60.0f);
  ASSERT_TRUE(validate_mesh(m).ok());
  for (const auto& n : m.normals) EXPECT_TRUE(n.allFinite());
  EXPECT_LT((m.normals[0] - Vec3(0, 0, 1)).norm(), 1e-6f);
  EXPECT_EQ(m.normals[4], Vec3::Zero());  // only degenerate faces around it
}

TEST(MeshNormals, MeshFromArraysComputesNormalsAndChecksInput) {
  const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<std::uint32_t> idx = {0, 1, 2};
  Result<Mesh> m = mesh_from_arrays(p, {}, idx);
  ASSERT_TRUE(m.ok()) << m.status().message();
  for (const auto& n : m->normals) EXPECT_EQ(n, Vec3(0, 0, 1));

  EXPECT_EQ(mesh_from_arrays(std::vector<float>{0, 0}, {}, idx).status().field(), "positions");
  EXPECT_EQ(mesh_from_arrays(p, {}, std::vector<std::uint32_t>{0, 1}).status().field(), "indices");
  EXPECT_EQ(mesh_from_arrays(p, std::vector<float>{0, 0, 1}, idx).status().field(), "normals");
  const Status bad = mesh_from_arrays(p, {}, std::vector<std::uint32_t>{0, 1, 3}).status();
  EXPECT_EQ(bad.field(), "indices");
  EXPECT_NE(bad.message().find("index 3 is out of range"), std::string::npos) << bad.message();
}

// Fandisk is a CAD part with sharp creases: at the default 60 deg, no corner normal may be more than
// 60 deg from its own face (a 90 deg edge smoothed would put it at 45 deg from both), sharp edges
// must be split, and the curved patches must still be smoothed.
TEST(MeshNormals, FandiskCreasesStaySharp) {
  FACET_REQUIRE_MODELS();
  Result<Mesh> loaded = load_obj(test::models_dir() + "/fandisk.obj");
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  const Mesh& m = *loaded;
  EXPECT_GT(m.vertex_count(), 6475u) << "vertices along creases must have been split";

  const float cos_crease = std::cos(60.0f * std::numbers::pi_v<float> / 180.0f);
  std::size_t smoothed = 0;
  // Corner normals by (welded position, triangle), to compare the two sides of each sharp edge.
  std::map<std::tuple<float, float, float>, std::vector<std::pair<std::size_t, Vec3>>> at_position;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 f = face_normal(m, m.triangles[t]);
    if (!f.allFinite()) continue;
    for (auto i : m.triangles[t]) {
      EXPECT_GE(m.normals[i].dot(f), cos_crease - 1e-5f) << "triangle " << t;
      if (m.normals[i].dot(f) < 0.9998f) ++smoothed;  // more than ~1 deg from the face
      const Vec3& p = m.positions[i];
      at_position[{p.x(), p.y(), p.z()}].push_back({t, m.normals[i]});
    }
  }
  EXPECT_GT(smoothed, 1000u) << "curved parts must be smoothed";

  // Across every sharp edge (faces more than 60 deg apart), the two sides use different normals.
  std::size_t sharp_pairs = 0;
  for (const auto& [pos, corners] : at_position) {
    for (std::size_t a = 0; a < corners.size(); ++a) {
      for (std::size_t b = a + 1; b < corners.size(); ++b) {
        const Vec3 fa = face_normal(m, m.triangles[corners[a].first]);
        const Vec3 fb = face_normal(m, m.triangles[corners[b].first]);
        if (!fa.allFinite() || !fb.allFinite() || fa.dot(fb) >= std::cos(70.0f * std::numbers::pi_v<float> / 180.0f)) continue;
        ++sharp_pairs;
        EXPECT_NE(corners[a].second, corners[b].second);
      }
    }
  }
  EXPECT_GT(sharp_pairs, 100u);
}

}  // namespace
}  // namespace facet
