// The lighting's data movement: the SSE2 AoS <-> SoA copies and the object bounding sphere that
// the frame plan culls lights against (both rewritten for speed; these hold them to their plain
// per-vertex definitions).
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "facet/facet.hpp"
#include "geometry/bounds.hpp"
#include "lighting/point_shader.hpp"
#include "lighting/setup.hpp"
#include "lighting/soa.hpp"

namespace facet::lighting {
namespace {

std::vector<Vec3> random_points(std::size_t n, float spread, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-spread, spread);
  std::vector<Vec3> p(n);
  for (auto& v : p) v = Vec3(u(rng), u(rng), u(rng)) + Vec3(3.0f, -1.0f, 0.5f) * spread;
  return p;
}

TEST(LightingSoa, DeinterleaveAndInterleaveAreExactForEveryTailLength) {
  for (std::size_t n = 0; n <= 13; ++n) {
    const std::vector<Vec3> p = random_points(n, 10.0f, static_cast<std::uint32_t>(n));
    std::vector<float> x(n + 1, 7.0f), y(n + 1, 7.0f), z(n + 1, 7.0f);
    deinterleave3(p.data(), n, -2.0f, x.data(), y.data(), z.data());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(x[i], -2.0f * p[i].x()) << n << " " << i;
      EXPECT_EQ(y[i], -2.0f * p[i].y()) << n << " " << i;
      EXPECT_EQ(z[i], -2.0f * p[i].z()) << n << " " << i;
    }
    EXPECT_EQ(x[n], 7.0f);  // nothing written past n
    EXPECT_EQ(z[n], 7.0f);
    std::vector<Vec3> back(n + 1, Vec3::Constant(5.0f));
    interleave3(x.data(), y.data(), z.data(), n, back.data());
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(back[i], (-2.0f * p[i]).eval()) << n << " " << i;
    EXPECT_EQ(back[n], Vec3::Constant(5.0f));
  }
}

// The indexed copy (the vertices a frame lights, through their index list), for every tail
// length, with repeated, descending and last-vertex indices: an exact copy times the scale.
TEST(LightingSoa, IndexedDeinterleaveIsExactForEveryTailLength) {
  const std::vector<Vec3> p = random_points(9, 10.0f, 42u);
  for (std::size_t n = 0; n <= 13; ++n) {
    std::vector<std::uint32_t> index(n);
    for (std::size_t i = 0; i < n; ++i) index[i] = static_cast<std::uint32_t>((i * 5 + 8) % p.size());
    std::vector<float> x(n + 1, 7.0f), y(n + 1, 7.0f), z(n + 1, 7.0f);
    deinterleave3(p.data(), index.data(), n, -2.0f, x.data(), y.data(), z.data());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(x[i], -2.0f * p[index[i]].x()) << n << " " << i;
      EXPECT_EQ(y[i], -2.0f * p[index[i]].y()) << n << " " << i;
      EXPECT_EQ(z[i], -2.0f * p[index[i]].z()) << n << " " << i;
    }
    EXPECT_EQ(x[n], 7.0f);
    EXPECT_EQ(y[n], 7.0f);
    EXPECT_EQ(z[n], 7.0f);
  }
}

double farthest_double(const std::vector<Vec3>& p, const Eigen::Vector3d& c) {
  double r2 = 0;
  for (const Vec3& v : p)
    if (v.allFinite()) r2 = std::max(r2, (v.cast<double>() - c).squaredNorm());
  return r2;
}

// The sphere holds every finite vertex and is no more than 1e-4 looser than the tight one around
// the same centre (the box centre, in eye space).
void expect_tight_bounds(const std::vector<Vec3>& positions, const Mat4& model) {
  Mesh mesh;
  mesh.positions = positions;
  const Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  const EyeSphere s = eye_bounding_sphere(mesh, view, model);
  const Eigen::Matrix4d m = model.cast<double>();
  const double stretch = m.topLeftCorner<3, 3>().norm();
  const Eigen::Vector3d c_model = (m.inverse() * s.centre.homogeneous()).head<3>();
  const double tight = std::sqrt(farthest_double(positions, c_model)) * stretch;
  // Slack for the double rounding of this check itself (the centre taken back to model space):
  // 1e-12 of the coordinates' size, far below float's rounding that the sphere must cover.
  double size = 0;
  for (const Vec3& v : positions)
    if (v.allFinite()) size = std::max(size, double(v.cwiseAbs().maxCoeff()));
  const double slack = 1e-12 * size * stretch;
  EXPECT_GE(s.radius, tight - slack);
  EXPECT_LE(s.radius, tight * (1 + 1e-4) + slack);
  for (const Vec3& v : positions) {
    if (!v.allFinite()) continue;
    const Eigen::Vector3d e = (m * v.cast<double>().homogeneous()).head<3>();
    EXPECT_LE((e - s.centre).norm(), s.radius + slack);
  }
}

TEST(LightingSoa, BoundingSphereHoldsEveryVertexForEveryTailLength) {
  Mat4 model = Mat4::Identity();
  model.block<3, 3>(0, 0) = Eigen::AngleAxisf(0.7f, Vec3(1, 2, 3).normalized()).toRotationMatrix() * 2.5f;
  model.block<3, 1>(0, 3) = Vec3(1, -4, -20);
  for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 13u, 1000u, 4099u}) {
    expect_tight_bounds(random_points(n, 3.0f, static_cast<std::uint32_t>(n)), model);
  }
  expect_tight_bounds(random_points(500, 1e17f, 1), Mat4::Identity());  // squares near float's limit
  expect_tight_bounds(random_points(500, 1e30f, 2), Mat4::Identity());  // beyond it: the double pass
}

TEST(LightingSoa, BoundingSphereLeavesOutNonFiniteVertices) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (const Vec3& bad : {Vec3(inf, 0, 0), Vec3(0, -inf, 0), Vec3(nan, 1, 1), Vec3(1, 1, nan)}) {
    for (std::size_t at : {0u, 5u, 12u, 16u}) {
      std::vector<Vec3> p = random_points(17, 2.0f, static_cast<std::uint32_t>(at));
      p[at] = bad;
      expect_tight_bounds(p, Mat4::Identity());
      Mesh mesh;
      mesh.positions = p;
      const EyeSphere s = eye_bounding_sphere(mesh, Eigen::Matrix4d::Identity(), Mat4::Identity());
      EXPECT_TRUE(std::isfinite(s.radius));
      EXPECT_LT(s.radius, 10.0);
    }
  }
  Mesh none;
  none.positions = {Vec3(nan, 0, 0), Vec3(inf, inf, inf)};
  EXPECT_EQ(eye_bounding_sphere(none, Eigen::Matrix4d::Identity(), Mat4::Identity()).radius, 0.0);
}

// Large meshes are bounded in chunks (bounds_chunk_size): the sphere holds every vertex and is the
// same whichever order the chunks run in (a parallel loop runs them in any), with a non-finite
// vertex in one chunk and a far vertex in another.
TEST(LightingSoa, BoundingSphereIsTheSameInAnyChunkOrder) {
  for (std::size_t n : {kBoundsChunkVertices * 3 + 5, kBoundsChunkVertices * kBoundsChunks * 2 + 77}) {
    Mesh mesh;
    mesh.positions = random_points(n, 3.0f, static_cast<std::uint32_t>(n));
    mesh.positions[n / 2] = Vec3(std::numeric_limits<float>::quiet_NaN(), 0, 0);
    mesh.positions[n - 3] = Vec3(40.0f, -7.0f, 2.0f);
    const Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
    const EyeSphere in_turn = eye_bounding_sphere(mesh, view, Mat4::Identity());
    std::size_t ran = 0;
    const EyeSphere reversed = eye_bounding_sphere(mesh, view, Mat4::Identity(), [&](std::size_t chunks, const auto& fn) {
      EXPECT_LE(chunks, kBoundsChunks);
      for (std::size_t c = chunks; c-- > 0;) fn(c), ++ran;
    });
    EXPECT_GT(ran, 2u);
    EXPECT_EQ(in_turn.centre, reversed.centre);
    EXPECT_EQ(in_turn.radius, reversed.radius);
    if (n < 100000) expect_tight_bounds(mesh.positions, Mat4::Identity());
  }
}

// The centre the float pass measures from is a float point in every coordinate (the bounds of an
// object off the axes took the double loop when Eigen's cast left one coordinate unrounded).
TEST(LightingSoa, BoundsCentreIsAFloatPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d lo(u(rng), u(rng), u(rng)), hi = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseAbs();
    const Eigen::Vector3d c = float_centre(lo, hi);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(double(float(c[k])), c[k]) << "coordinate " << k;
      EXPECT_NEAR(c[k], 0.5 * (lo[k] + hi[k]), 1e-5 * (std::abs(lo[k]) + std::abs(hi[k])));
    }
  }
}

// Each ISA's box of xyz triples (light_instance's chunks) against the scalar finite_box: the same
// floats for every length up to past two avx512 batches, and false (the scalar pass takes over)
// when a NaN or an infinity is anywhere, batch or tail.
TEST(LightingSoa, SimdBoxIsTheScalarBoxOrDeclines) {
  int compared = 0;
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    const SimdKernels* k = simd_kernels(isa);
    if (!k) continue;
    for (std::size_t n = 1; n <= 37; ++n) {
      std::vector<Vec3> p = random_points(n, 10.0f, static_cast<std::uint32_t>(100 + n));
      Eigen::Vector3d lo, hi;
      ASSERT_TRUE(geometry::finite_box(p.data(), n, lo, hi));
      float flo[3], fhi[3];
      ASSERT_TRUE(k->box(p.data()->data(), n, flo, fhi)) << to_string(isa) << " " << n;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(double(flo[c]), lo[c]) << to_string(isa) << " " << n << " " << c;
        EXPECT_EQ(double(fhi[c]), hi[c]) << to_string(isa) << " " << n << " " << c;
      }
      for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity()}) {
        for (std::size_t at : {std::size_t{0}, n / 2, n - 1}) {
          std::vector<Vec3> q = p;
          q[at][static_cast<int>(at % 3)] = bad;
          EXPECT_FALSE(k->box(q.data()->data(), n, flo, fhi)) << to_string(isa) << " " << n << " at " << at;
        }
      }
      ++compared;
    }
  }
  EXPECT_GE(compared, 37);
}

}  // namespace
}  // namespace facet::lighting
