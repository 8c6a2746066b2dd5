// The vertex kernels of animated meshes: the scalar twin, the double reference and the dispatch
// to the per-ISA files (skin.hpp). Compiled with -ffp-contract=off and without auto-vectorisation
// (engine/CMakeLists.txt): an honest one-vertex-at-a-time baseline with the SIMD files' rounding.
#if !defined(FACET_NO_FP_CONTRACT)
#error "skin.cpp must be compiled with -ffp-contract=off (the same bits as the SIMD kernels)"
#endif

#include "geometry/skin.hpp"

#include <cmath>

#include "geometry/skin_math.hpp"

namespace facet::geometry {

void morph_scalar(const MorphJob& job) {
  for (int c = 0; c < 3; ++c) {
    const float* base = job.base[c];
    float* out = job.out[c];
    if (!base || !out) continue;
    for (std::size_t i = 0; i < job.count; ++i) {
      float v = base[i];
      for (std::size_t t = 0; t < job.target_count; ++t) {
        const float* d = job.targets[t].delta[c];
        if (d) v = v + job.targets[t].weight * d[i];
      }
      out[i] = v;
    }
  }
}

void skin_scalar(const SkinJob& job) {
  const std::size_t n = job.count;
  for (std::size_t i = 0; i < n; ++i) {
    skin_math::Blend<float> b;
    b.first(job.weights[i], job.matrices + 12 * std::size_t(job.joints[i]));
    for (int k = 1; k < job.influences; ++k) {
      const float w = job.weights[std::size_t(k) * n + i];
      b.add(w, job.matrices + 12 * std::size_t(job.joints[std::size_t(k) * n + i]));
    }
    float p[3];
    b.point(job.position[0][i], job.position[1][i], job.position[2][i], p);
    for (int r = 0; r < 3; ++r) job.out_position[3 * i + r] = p[r];
    if (job.normal[0] && job.out_normal) {
      float v[3];
      if (job.normals == NormalTransform::cofactor) b.cofactor(job.normal[0][i], job.normal[1][i], job.normal[2][i], v);
      else b.vector(job.normal[0][i], job.normal[1][i], job.normal[2][i], v);
      skin_math::normalise(v);
      for (int r = 0; r < 3; ++r) job.out_normal[3 * i + r] = v[r];
    }
    if (job.tangent[0] && job.out_tangent) {
      float v[3];
      b.vector(job.tangent[0][i], job.tangent[1][i], job.tangent[2][i], v);
      skin_math::normalise(v);
      for (int r = 0; r < 3; ++r) job.out_tangent[4 * i + r] = v[r];
    }
  }
}

void skin_reference(const SkinJob& job, const double* matrices, double* out_position, double* out_normal,
                    double* out_tangent) {
  const std::size_t n = job.count;
  auto unit = [](double* v) {
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int r = 0; r < 3; ++r) v[r] = len > 0.0 ? v[r] / len : 0.0;
  };
  for (std::size_t i = 0; i < n; ++i) {
    double m[12] = {};
    for (int k = 0; k < job.influences; ++k) {
      const double w = job.weights[std::size_t(k) * n + i];
      const double* j = matrices + 12 * std::size_t(job.joints[std::size_t(k) * n + i]);
      for (int e = 0; e < 12; ++e) m[e] += w * j[e];
    }
    const double p[3] = {job.position[0][i], job.position[1][i], job.position[2][i]};
    for (int r = 0; r < 3; ++r) out_position[3 * i + r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
    if (job.normal[0] && out_normal) {
      const double q[3] = {job.normal[0][i], job.normal[1][i], job.normal[2][i]};
      double v[3];
      if (job.normals == NormalTransform::cofactor) {
        // The inverse transpose itself (Cramer's rule), not the kernels' cofactor form.
        const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                           m[2] * (m[4] * m[9] - m[5] * m[8]);
        const double inv[9] = {(m[5] * m[10] - m[6] * m[9]) / det,  (m[2] * m[9] - m[1] * m[10]) / det, (m[1] * m[6] - m[2] * m[5]) / det,
                               (m[6] * m[8] - m[4] * m[10]) / det,  (m[0] * m[10] - m[2] * m[8]) / det, (m[2] * m[4] - m[0] * m[6]) / det,
                               (m[4] * m[9] - m[5] * m[8]) / det,   (m[1] * m[8] - m[0] * m[9]) / det,  (m[0] * m[5] - m[1] * m[4]) / det};
        // (A^-1)^T q: row r of the transpose is column r of the inverse.
        for (int r = 0; r < 3; ++r) v[r] = inv[r] * q[0] + inv[3 + r] * q[1] + inv[6 + r] * q[2];
        if (!std::isfinite(v[0] + v[1] + v[2])) v[0] = v[1] = v[2] = 0.0;
      } else {
        for (int r = 0; r < 3; ++r) v[r] = m[4 * r] * q[0] + m[4 * r + 1] * q[1] + m[4 * r + 2] * q[2];
      }
      unit(v);
      for (int r = 0; r < 3; ++r) out_normal[3 * i + r] = v[r];
    }
    if (job.tangent[0] && out_tangent) {
      const double q[3] = {job.tangent[0][i], job.tangent[1][i], job.tangent[2][i]};
      double v[3];
      for (int r = 0; r < 3; ++r) v[r] = m[4 * r] * q[0] + m[4 * r + 1] * q[1] + m[4 * r + 2] * q[2];
      unit(v);
      for (int r = 0; r < 3; ++r) out_tangent[4 * i + r] = v[r];
    }
  }
}

namespace {
// An ISA this CPU lacks runs the scalar twin: the same bits.
Isa chosen(Isa isa) {
  if (isa == Isa::best) return best_isa();
  return isa_supported(isa) ? isa : Isa::best;
}
}  // namespace

void morph(const MorphJob& job, Isa isa) {
  switch (chosen(isa)) {
    case Isa::avx512: simd::avx512::morph(job); return;
    case Isa::avx2: simd::avx2::morph(job); return;
    case Isa::sse2: simd::sse2::morph(job); return;
    case Isa::best: morph_scalar(job); return;
  }
}

void skin(const SkinJob& job, Isa isa) {
  switch (chosen(isa)) {
    case Isa::avx512: simd::avx512::skin(job); return;
    case Isa::avx2: simd::avx2::skin(job); return;
    case Isa::sse2: simd::sse2::skin(job); return;
    case Isa::best: skin_scalar(job); return;
  }
}

}  // namespace facet::geometry
