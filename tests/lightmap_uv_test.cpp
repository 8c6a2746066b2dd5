// Lightmap charts and their atlas (unwrap_lightmap): every triangle mapped into its chart's
// rectangle, the rectangles padded apart inside the atlas, no two triangles sharing a texel's
// sample, orientation kept, and the density each triangle gets within [cos(chart angle), 1] of
// the requested one; on procedural shapes, a self-overlapping ramp and real models.
#include <cmath>
#include <numbers>

#include "facet/lightmap.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

struct Report {
  std::size_t charts = 0, overlapping_samples = 0;
  double min_density = 1e300, max_density = 0;
};

// Checks every property the header promises; returns what the caller wants to compare further.
Report check_unwrap(const Mesh& mesh, const LightmapUvOptions& o, const std::string& name) {
  SCOPED_TRACE(name);
  Report r;
  const Result<LightmapUnwrap> result = unwrap_lightmap(mesh, o);
  EXPECT_TRUE(result.ok()) << result.status().message();
  if (!result.ok()) return r;
  const LightmapUnwrap& u = *result;
  r.charts = u.charts.size();
  EXPECT_LE(u.width, o.max_size);
  EXPECT_LE(u.height, o.max_size);
  EXPECT_EQ(u.triangles.size(), mesh.triangles.size());
  EXPECT_EQ(u.chart_of_triangle.size(), mesh.triangles.size());
  EXPECT_EQ(u.uvs.size(), u.source_vertex.size());
  const int pad = o.padding;
  // Rectangles inside the atlas with its padding, and at least `padding` texels apart.
  for (std::size_t i = 0; i < u.charts.size(); ++i) {
    const auto& a = u.charts[i];
    EXPECT_GE(a.x0, pad);
    EXPECT_GE(a.y0, pad);
    EXPECT_LE(a.x0 + a.w + pad, u.width);
    EXPECT_LE(a.y0 + a.h + pad, u.height);
    for (std::size_t j = i + 1; j < u.charts.size(); ++j) {
      const auto& b = u.charts[j];
      const bool apart = a.x0 + a.w + pad <= b.x0 || b.x0 + b.w + pad <= a.x0 || a.y0 + a.h + pad <= b.y0 ||
                         b.y0 + b.h + pad <= a.y0;
      if (!apart) {
        ADD_FAILURE() << "charts " << i << " and " << j << " closer than the padding";
        return r;
      }
    }
  }
  // Every corner a copy of its input vertex, inside its chart's rectangle (half a texel in).
  const double cos_limit = std::cos(o.chart_angle_deg * std::numbers::pi / 180.0);
  std::vector<int> coverage(static_cast<std::size_t>(u.width) * static_cast<std::size_t>(u.height) * 16);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& rect = u.charts[u.chart_of_triangle[t]];
    std::array<Eigen::Vector2d, 3> p;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = u.triangles[t][static_cast<std::size_t>(k)];
      EXPECT_EQ(u.source_vertex[v], mesh.triangles[t][static_cast<std::size_t>(k)]);
      p[static_cast<std::size_t>(k)] = Eigen::Vector2d(double(u.uvs[v].x()) * u.width, double(u.uvs[v].y()) * u.height);
      const auto& q = p[static_cast<std::size_t>(k)];
      const double slack = 1e-3;
      if (!(q.x() >= rect.x0 + 0.5 - slack && q.x() <= rect.x0 + rect.w - 0.5 + slack && q.y() >= rect.y0 + 0.5 - slack &&
            q.y() <= rect.y0 + rect.h - 0.5 + slack)) {
        ADD_FAILURE() << "triangle " << t << " corner " << k << " outside its chart";
        return r;
      }
    }
    const Eigen::Vector3d a = mesh.positions[mesh.triangles[t][0]].cast<double>(),
                          b = mesh.positions[mesh.triangles[t][1]].cast<double>(),
                          c = mesh.positions[mesh.triangles[t][2]].cast<double>();
    const double world = 0.5 * (b - a).cross(c - a).norm();
    const double texels = 0.5 * cross2(p[1] - p[0], p[2] - p[0]);
    if (world > 0) {
      // Orientation kept, density within [cos(chart angle), 1] of the requested (area ratio).
      const double d = texels / (world * o.texels_per_unit * o.texels_per_unit);
      r.min_density = std::min(r.min_density, d);
      r.max_density = std::max(r.max_density, d);
      // Samples 4x4 a texel, strictly inside (an edge shared by two triangles counts for neither).
      const Eigen::Vector2d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
      for (int sy = static_cast<int>(std::floor(lo.y() * 4)); sy <= static_cast<int>(std::ceil(hi.y() * 4)); ++sy) {
        for (int sx = static_cast<int>(std::floor(lo.x() * 4)); sx <= static_cast<int>(std::ceil(hi.x() * 4)); ++sx) {
          const Eigen::Vector2d s((sx + 0.37) / 4, (sy + 0.61) / 4);
          bool inside = true;
          for (int k = 0; k < 3; ++k) {
            const double e = cross2(p[static_cast<std::size_t>((k + 1) % 3)] - p[static_cast<std::size_t>(k)], s - p[static_cast<std::size_t>(k)]);
            inside = inside && e > 1e-9;
          }
          if (!inside || sx < 0 || sy < 0 || sx >= u.width * 4 || sy >= u.height * 4) continue;
          int& n = coverage[static_cast<std::size_t>(sy) * static_cast<std::size_t>(u.width) * 4 + static_cast<std::size_t>(sx)];
          r.overlapping_samples += n > 0;
          ++n;
        }
      }
    } else {
      EXPECT_EQ(texels, 0.0) << "a triangle without area covers texels";
    }
  }
  EXPECT_EQ(r.overlapping_samples, 0u);
  if (r.max_density > 0) {
    EXPECT_GT(r.min_density, 0.0) << "orientation flipped or area lost";
    EXPECT_GE(r.min_density, cos_limit - 1e-4);
    EXPECT_LE(r.max_density, 1.0 + 1e-4);
  }
  return r;
}

TEST(LightmapUv, PlaneIsOneChartOfItsSizeAtTheDensity) {
  LightmapUvOptions o;
  o.texels_per_unit = 10;
  o.padding = 3;
  const Mesh plane = make_plane(4.0f, 2.0f, 8);
  const Report r = check_unwrap(plane, o, "plane");
  EXPECT_EQ(r.charts, 1u);
  EXPECT_NEAR(r.min_density, 1.0, 1e-6);
  const Result<LightmapUnwrap> u = unwrap_lightmap(plane, o);
  ASSERT_TRUE(u.ok());
  // 40 x 20 texels of extent, one more for the half texels at each end.
  EXPECT_EQ(std::max(u->charts[0].w, u->charts[0].h), 41);
  EXPECT_EQ(std::min(u->charts[0].w, u->charts[0].h), 21);
}

TEST(LightmapUv, CubeFacesAreSixCharts) {
  LightmapUvOptions o;
  o.texels_per_unit = 16;
  const Report r = check_unwrap(make_cube(2.0f, 4), o, "cube");
  EXPECT_EQ(r.charts, 6u);
  EXPECT_NEAR(r.min_density, 1.0, 1e-6);
}

TEST(LightmapUv, CurvedShapesKeepTheirContract) {
  for (double angle : {20.0, 45.0, 70.0}) {
    LightmapUvOptions o;
    o.texels_per_unit = 24;
    o.chart_angle_deg = angle;
    const Report sphere = check_unwrap(make_uv_sphere(1.0f, 48, 24), o, "sphere");
    EXPECT_GT(sphere.charts, 2u);
    check_unwrap(make_torus(1.0f, 0.3f, 40, 16), o, "torus");
  }
  LightmapUvOptions o;
  o.padding = 1;
  o.texels_per_unit = 4;
  check_unwrap(make_uv_sphere(1.0f, 16, 8), o, "coarse sphere, padding 1");
}

// A ramp that climbs gently around a circle twice: every triangle faces almost up, so they would
// all join one chart, but the second turn lies over the first in the projection. The chart must
// stop where it would overlap itself.
TEST(LightmapUv, SelfOverlappingRampIsSplit) {
  Mesh m;
  const int steps = 160;
  for (int i = 0; i <= steps; ++i) {
    const double a = 4 * std::numbers::pi * i / steps;
    for (double radius : {1.0, 1.5}) {
      m.positions.push_back(Vec3(float(radius * std::cos(a)), float(radius * std::sin(a)), float(0.05 * a)));
      m.normals.push_back(Vec3(0, 0, 1));
    }
  }
  for (int i = 0; i < steps; ++i) {
    const auto b = static_cast<std::uint32_t>(2 * i);
    m.triangles.push_back({b, b + 1, b + 3});
    m.triangles.push_back({b, b + 3, b + 2});
  }
  LightmapUvOptions o;
  o.texels_per_unit = 32;
  const Report r = check_unwrap(m, o, "ramp");
  EXPECT_GE(r.charts, 2u);
}

TEST(LightmapUv, DegenerateAndNonManifoldTriangles) {
  Mesh m = make_cube(1.0f, 2);
  m.uvs.clear(), m.tangents.clear();
  const auto n = static_cast<std::uint32_t>(m.positions.size());
  // Zero-area triangles (a repeated corner, three collinear points) share one chart.
  m.triangles.push_back({0, 0, 1});
  m.positions.push_back(Vec3(0, 0, 0)), m.positions.push_back(Vec3(1, 1, 1)), m.positions.push_back(Vec3(2, 2, 2));
  m.normals.resize(m.positions.size(), Vec3(0, 0, 1));
  m.triangles.push_back({n, n + 1, n + 2});
  // Three triangles on one edge (a fin).
  const auto f = static_cast<std::uint32_t>(m.positions.size());
  for (const Vec3& p : {Vec3(3, 0, 0), Vec3(3, 1, 0), Vec3(4, 0.5f, 0), Vec3(3, 0.5f, 1), Vec3(2, 0.5f, 0.2f)}) {
    m.positions.push_back(p);
    m.normals.push_back(Vec3(0, 0, 1));
  }
  m.triangles.push_back({f, f + 2, f + 1});
  m.triangles.push_back({f, f + 1, f + 3});
  m.triangles.push_back({f, f + 4, f + 1});
  LightmapUvOptions o;
  o.texels_per_unit = 8;
  check_unwrap(m, o, "cube with degenerate triangles and a fin");
}

TEST(LightmapUv, RefusesBadOptionsAndOversizedAtlases) {
  const Mesh cube = make_cube(1.0f, 1);
  auto field = [&](LightmapUvOptions o) { return unwrap_lightmap(cube, o).status().field(); };
  LightmapUvOptions o;
  o.texels_per_unit = 0;
  EXPECT_EQ(field(o), "texels_per_unit");
  o = {};
  o.texels_per_unit = std::nan("");
  EXPECT_EQ(field(o), "texels_per_unit");
  o = {};
  o.padding = 0;
  EXPECT_EQ(field(o), "padding");
  o = {};
  o.chart_angle_deg = 90;
  EXPECT_EQ(field(o), "chart_angle_deg");
  o = {};
  o.max_size = 0;
  EXPECT_EQ(field(o), "max_size");
  // A density far beyond the budget is refused with what would fit, before an atlas is made.
  o = {};
  o.texels_per_unit = 1e7;
  const Status st = unwrap_lightmap(cube, o).status();
  EXPECT_EQ(st.code(), ErrorCode::out_of_memory);
  EXPECT_EQ(st.field(), "texels_per_unit");
  EXPECT_NE(st.message().find("would fit"), std::string::npos) << st.message();
  // And the density it names does fit.
  const std::size_t at = st.message().find("; ") + 2;
  o.texels_per_unit = std::stod(st.message().substr(at));
  EXPECT_GT(o.texels_per_unit, 1000);  // 6 faces of 1 x 1 in 8192 x 8192 texels: about 2700
  EXPECT_TRUE(unwrap_lightmap(cube, o).ok()) << o.texels_per_unit;
  Mesh broken = cube;
  broken.triangles[0][1] = 999;
  EXPECT_EQ(unwrap_lightmap(broken).status().field(), "mesh.triangles[0]");
}

TEST(LightmapUv, RealModels) {
  FACET_REQUIRE_MODELS();
  for (const char* file : {"fandisk.obj", "spot.obj", "teapot.obj", "suzanne.obj"}) {
    Result<Mesh> m = load_obj(test::models_dir() + "/" + file);
    ASSERT_TRUE(m.ok()) << m.status().message();
    LightmapUvOptions o;
    o.texels_per_unit = 64;
    const Report r = check_unwrap(*m, o, file);
    EXPECT_GT(r.charts, 1u) << file;
  }
}

}  // namespace
}  // namespace facet
