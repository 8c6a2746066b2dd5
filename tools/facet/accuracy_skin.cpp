// `facet accuracy`, part 12: skinned normals. Random vertices bent by four of 32 random joints
// (a rotation within 30 degrees of the others', a translation, and a scale that is even, or
// uneven by 1.5 or 3 across the axes),
// by the cofactor transform and the plain 3x3 (NormalTransform), on the scalar twin and the best
// ISA's kernel, against the double reference's inverse transpose: the angle between the normals
// (degrees) and the vertices skinned per second on one thread. The SIMD kernel must match the
// scalar twin bit for bit; the cofactor transform must stay within 1e-3 degrees.
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "accuracy.hpp"
#include "geometry/skin.hpp"

namespace facet::cli {
namespace {

struct SkinInput {
  std::size_t n = 0, joints = 32;
  std::vector<float> in[6], weights, matrices;
  std::vector<double> matrices_d;
  std::vector<std::uint16_t> index;
  SkinInput(std::size_t count, double uneven, unsigned seed) : n(count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto& s : in) {
      s.resize(n);
      for (float& v : s) v = float(u(rng));
    }
    index.resize(4 * n);
    weights.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      double w[4], sum = 0;
      for (int k = 0; k < 4; ++k) sum += w[k] = 0.6 + 0.4 * u(rng);
      for (int k = 0; k < 4; ++k) index[std::size_t(k) * n + i] = std::uint16_t(rng() % joints), weights[std::size_t(k) * n + i] = float(w[k] / sum);
    }
    matrices.resize(12 * joints);
    matrices_d.resize(12 * joints);
    for (std::size_t j = 0; j < joints; ++j) {
      // As a skeleton's neighbouring joints: turned within 30 degrees of one another.
      const Eigen::Matrix3d r = Eigen::AngleAxisd(std::numbers::pi / 6 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng) + 2.0).normalized())
                                    .toRotationMatrix();
      const Eigen::Vector3d scale(1.0, uneven, 1.0 / uneven);
      const Eigen::Matrix3d m = r * scale.asDiagonal();
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) matrices[12 * j + std::size_t(4 * row + col)] = float(m(row, col));
        matrices[12 * j + std::size_t(4 * row + 3)] = float(2.0 * u(rng));
      }
      for (std::size_t e = 0; e < 12; ++e) matrices_d[12 * j + e] = matrices[12 * j + e];
    }
  }
  geometry::SkinJob job(NormalTransform normals, float* p, float* nrm) const {
    geometry::SkinJob jb;
    jb.count = n;
    for (int c = 0; c < 3; ++c) jb.position[c] = in[c].data(), jb.normal[c] = in[3 + c].data();
    jb.influences = 4;
    jb.joints = index.data();
    jb.weights = weights.data();
    jb.matrices = matrices.data();
    jb.joint_count = joints;
    jb.normals = normals;
    jb.out_position = p;
    jb.out_normal = nrm;
    return jb;
  }
};

// Vertices per second of `run` on one thread: repeated for at least 0.1 s (0.02 s quick).
template <class Fn>
double rate_of(std::size_t n, bool quick, Fn&& run) {
  const auto start = std::chrono::steady_clock::now();
  double seconds = 0;
  long rounds = 0;
  do {
    run();
    ++rounds;
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } while (seconds < (quick ? 0.02 : 0.1));
  return double(rounds) * double(n) / seconds;
}

}  // namespace

Status skin_accuracy(bool quick, std::vector<Row>& rows) {
  const std::size_t n = quick ? 8192 : 65536;
  for (const double uneven : {1.0, 1.5, 3.0}) {
    const SkinInput input(n, uneven, 11);
    std::vector<double> ref_p(3 * n), ref_n(3 * n);
    {
      std::vector<float> p(3 * n), nrm(3 * n);
      const geometry::SkinJob exact = input.job(NormalTransform::cofactor, p.data(), nrm.data());
      geometry::skin_reference(exact, input.matrices_d.data(), ref_p.data(), ref_n.data(), nullptr);
    }
    for (const NormalTransform nt : {NormalTransform::cofactor, NormalTransform::linear}) {
      std::vector<float> twin_p(3 * n), twin_n(3 * n), simd_p(3 * n), simd_n(3 * n);
      const geometry::SkinJob twin = input.job(nt, twin_p.data(), twin_n.data());
      const geometry::SkinJob fast = input.job(nt, simd_p.data(), simd_n.data());
      const double twin_rate = rate_of(n, quick, [&] { geometry::skin_scalar(twin); });
      const double simd_rate = rate_of(n, quick, [&] { geometry::skin(fast, Isa::best); });
      const bool identical = std::memcmp(twin_p.data(), simd_p.data(), 12 * n) == 0 && std::memcmp(twin_n.data(), simd_n.data(), 12 * n) == 0;
      double worst = 0, sum = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d a(twin_n[3 * i], twin_n[3 * i + 1], twin_n[3 * i + 2]), b(ref_n[3 * i], ref_n[3 * i + 1], ref_n[3 * i + 2]);
        const double angle = std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi;
        worst = std::max(worst, angle), sum += angle;
      }
      const char* name = nt == NormalTransform::cofactor ? "cofactor" : "linear 3x3";
      char item[64];
      std::snprintf(item, sizeof item, "scale 1 : %g : %g", uneven, 1.0 / uneven);
      for (const bool simd : {false, true}) {
        Row r;
        r.kind = "skin";
        r.method = std::string(name) + (simd ? std::string(" simd ") + to_string(best_isa()) : " scalar");
        r.item = item;
        r.max_lsb = worst;  // degrees
        r.mean_lsb = sum / double(n);
        r.rate = simd ? simd_rate : twin_rate;
        r.verdict = "ok";
        if (simd && !identical) r.verdict = "the SIMD kernel differs from the scalar twin";
        if (nt == NormalTransform::cofactor && worst > 1e-3) r.verdict = "normals over 1e-3 degrees from the inverse transpose";
        rows.push_back(r);
      }
    }
  }
  return {};
}

}  // namespace facet::cli
