// The skinning and morph kernels (geometry/skin.hpp): every ISA's output is bit-identical to the
// scalar twin (the stated contract: same operations, same order, no contraction), and the twin is
// within float rounding of the double reference; the cofactor normal transform is exact under a
// non-uniform scale where the plain 3x3 is not.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "facet/lighting.hpp"
#include "geometry/skin.hpp"

namespace facet::geometry {
namespace {

struct SkinCase {
  std::size_t count = 0, joints = 0;
  int influences = 4;
  std::vector<float> streams[9];
  std::vector<std::uint16_t> joint_index;
  std::vector<float> weights, matrices;
  std::vector<double> matrices_d;

  SkinCase(std::size_t n, std::size_t j, int k, unsigned seed, bool uneven_scale, bool mirrored = false)
      : count(n), joints(j), influences(k) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (auto& s : streams) {
      s.resize(n);
      for (float& v : s) v = u(rng);
    }
    joint_index.resize(std::size_t(k) * n);
    weights.resize(std::size_t(k) * n);
    for (std::size_t i = 0; i < n; ++i) {
      float sum = 0.0f;
      for (int c = 0; c < k; ++c) {
        joint_index[std::size_t(c) * n + i] = static_cast<std::uint16_t>(rng() % j);
        const float w = c == k - 1 && i % 3 == 0 ? 0.0f : 0.5f + 0.5f * u(rng);  // some zero weights
        weights[std::size_t(c) * n + i] = w;
        sum += w;
      }
      for (int c = 0; c < k; ++c) weights[std::size_t(c) * n + i] /= sum;
    }
    matrices.resize(12 * j);
    matrices_d.resize(12 * j);
    for (std::size_t m = 0; m < j; ++m) {
      // A rotation about a random axis, a scale (uneven if asked) and a translation.
      const double angle = 3.0 * u(rng);
      double axis[3] = {u(rng), u(rng), u(rng) + 2.0};
      const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
      for (double& a : axis) a /= len;
      const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
      const double x = axis[0], y = axis[1], z = axis[2];
      const double r[9] = {t * x * x + c, t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c,
                           t * y * z - s * x, t * x * z - s * y, t * y * z + s * x, t * z * z + c};
      const double scale[3] = {mirrored ? -1.0 : 1.0, uneven_scale ? 3.0 : 1.0, uneven_scale ? 0.25 : 1.0};
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) {
          const float v = float(r[3 * row + col] * scale[col]);
          matrices[12 * m + 4 * std::size_t(row) + std::size_t(col)] = v;
        }
        matrices[12 * m + 4 * std::size_t(row) + 3] = 4.0f * u(rng);
      }
      for (std::size_t e = 0; e < 12; ++e) matrices_d[12 * m + e] = matrices[12 * m + e];  // the same matrices, in double
    }
  }
  SkinJob job(NormalTransform normals) const {
    SkinJob jb;
    jb.count = count;
    for (int c = 0; c < 3; ++c) jb.position[c] = streams[c].data(), jb.normal[c] = streams[3 + c].data(), jb.tangent[c] = streams[6 + c].data();
    jb.influences = influences;
    jb.joints = joint_index.data();
    jb.weights = weights.data();
    jb.matrices = matrices.data();
    jb.joint_count = joints;
    jb.normals = normals;
    return jb;
  }
};

// The same floats bit for bit (an empty vector's data() may be null: memcmp is not called on it).
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

struct SkinOut {
  std::vector<float> p, n, t;
  explicit SkinOut(std::size_t count) : p(3 * count, -7.0f), n(3 * count, -7.0f), t(4 * count, -7.0f) {}
  void into(SkinJob& j) { j.out_position = p.data(), j.out_normal = n.data(), j.out_tangent = t.data(); }
};

TEST(SkinKernel, EveryIsaMatchesTheScalarTwinBitForBit) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{16}, std::size_t{37}, std::size_t{1000}}) {
    for (const int k : {1, 4, 8}) {
      for (const NormalTransform nt : {NormalTransform::cofactor, NormalTransform::linear}) {
        const SkinCase c(n, 5, k, unsigned(n * 31 + std::size_t(k)), true);
        SkinJob job = c.job(nt);
        SkinOut want(n);
        want.into(job);
        skin_scalar(job);
        for (const Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
          if (!isa_supported(isa)) continue;
          SCOPED_TRACE(std::string(to_string(isa)) + " n=" + std::to_string(n) + " k=" + std::to_string(k));
          SkinOut got(n);
          got.into(job);
          skin(job, isa);
          EXPECT_TRUE(same_bits(got.p, want.p));
          EXPECT_TRUE(same_bits(got.n, want.n));
          EXPECT_TRUE(same_bits(got.t, want.t));  // w (-7) kept too
        }
      }
    }
  }
}

TEST(SkinKernel, TheTwinIsWithinFloatRoundingOfTheReference) {
  // Joints scaled unevenly, and (second round) mirrored: a negative determinant, whose cofactor
  // matrix must be negated to point normals out of the surface.
  for (const bool mirrored : {false, true}) {
  SCOPED_TRACE(mirrored ? "mirrored" : "not mirrored");
  const std::size_t n = 4000;
  const SkinCase c(n, 12, 8, 99, true, mirrored);
  SkinJob job = c.job(NormalTransform::cofactor);
  SkinOut got(n);
  got.into(job);
  skin_scalar(job);
  std::vector<double> p(3 * n), nn(3 * n), t(4 * n);
  skin_reference(job, c.matrices_d.data(), p.data(), nn.data(), t.data());
  double worst_p = 0, worst_n = 0, worst_t = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double scale = 1.0;
    for (int r = 0; r < 3; ++r) scale = std::max(scale, std::abs(p[3 * i + std::size_t(r)]));
    for (int r = 0; r < 3; ++r) {
      worst_p = std::max(worst_p, std::abs(got.p[3 * i + std::size_t(r)] - p[3 * i + std::size_t(r)]) / scale);
      worst_n = std::max(worst_n, std::abs(got.n[3 * i + std::size_t(r)] - nn[3 * i + std::size_t(r)]));
      worst_t = std::max(worst_t, std::abs(got.t[4 * i + std::size_t(r)] - t[4 * i + std::size_t(r)]));
    }
  }
  // Bounds: a few float ulps of the operands (docs/animation.md gives the measured worst).
  std::printf("skin twin against the double reference: positions %.3g (relative), normals %.3g, tangents %.3g\n", worst_p,
              worst_n, worst_t);
  EXPECT_LT(worst_p, 4e-6) << worst_p;
  EXPECT_LT(worst_n, 2e-5) << worst_n;
  EXPECT_LT(worst_t, 2e-5) << worst_t;
  }
}

TEST(SkinKernel, TheCofactorTransformKeepsNormalsPerpendicular) {
  // Under a non-uniform scale only the inverse transpose (here the cofactor form) keeps a normal
  // perpendicular to the transformed surface; the plain 3x3 does not.
  const std::size_t n = 512;
  const SkinCase c(n, 3, 1, 5, true);
  for (const NormalTransform nt : {NormalTransform::cofactor, NormalTransform::linear}) {
    SkinJob job = c.job(nt);
    // Tangent streams perpendicular to the normals: t' = M t stays in the surface.
    std::vector<float> tangent[3];
    for (auto& s : tangent) s.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double a[3] = {c.streams[3][i], c.streams[4][i], c.streams[5][i]};
      const double b[3] = {0.3, -0.7, 0.2};
      const double x[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      for (int r = 0; r < 3; ++r) tangent[r][i] = float(x[r]);
    }
    for (int r = 0; r < 3; ++r) job.tangent[r] = tangent[r].data();
    SkinOut out(n);
    out.into(job);
    skin(job, Isa::best);
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double d = 0;
      for (int r = 0; r < 3; ++r) d += double(out.n[3 * i + std::size_t(r)]) * out.t[4 * i + std::size_t(r)];
      worst = std::max(worst, std::abs(d));
    }
    if (nt == NormalTransform::cofactor) EXPECT_LT(worst, 1e-5);
    else EXPECT_GT(worst, 0.1);  // the plain 3x3 tilts normals under a 3 : 0.25 scale
  }
}

TEST(SkinKernel, MorphAddsWeightedDeltasOnEveryIsa) {
  const std::size_t n = 45;
  std::vector<float> base(n), d0(n), d1(n);
  for (std::size_t i = 0; i < n; ++i) base[i] = float(i), d0[i] = 0.5f, d1[i] = float(i % 3);
  const MorphTarget targets[2] = {{{d0.data(), nullptr, d0.data()}, 0.25f}, {{d1.data(), d1.data(), nullptr}, -2.0f}};
  MorphJob job;
  job.count = n;
  for (int c = 0; c < 3; ++c) job.base[c] = base.data();
  job.targets = targets;
  job.target_count = 2;
  std::vector<float> want[3], got[3];
  for (int c = 0; c < 3; ++c) want[c].resize(n), job.out[c] = want[c].data();
  morph_scalar(job);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(want[0][i], float(i) + 0.125f - 2.0f * float(i % 3));
    EXPECT_EQ(want[1][i], float(i) - 2.0f * float(i % 3));
    EXPECT_EQ(want[2][i], float(i) + 0.125f);
  }
  for (const Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (!isa_supported(isa)) continue;
    for (int c = 0; c < 3; ++c) got[c].assign(n, -1.0f), job.out[c] = got[c].data();
    morph(job, isa);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(got[c], want[c]) << to_string(isa);
  }
}

}  // namespace
}  // namespace facet::geometry
