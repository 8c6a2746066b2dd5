// Internal: the morph and skinning kernels (skin.hpp) W vertices at a time, a template on the
// xsimd architecture, included only by skin_{sse2,avx2,avx512}.cpp (each compiled with its ISA's
// flags and -ffp-contract=off). The arithmetic is skin_math.hpp's, as in the scalar twin. Each
// vertex's joint matrices are blended with whole-row vector loads (12 elements, k influences),
// then the W blended matrices are turned into 12 element batches by 12 gathers from the stack
// (gathering every joint's elements per lane instead takes 12 k gathers and was slower:
// bench/results/2026-11-29-skinning.md); the position, normal and tangent math runs on the batches.
// The tail of fewer than W vertices runs through the same code on padded copies.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <immintrin.h>

#include <xsimd/xsimd.hpp>

#include "common/gather_simd.hpp"
#include "geometry/skin.hpp"
#include "geometry/skin_math.hpp"

namespace facet::geometry::simd {
namespace {

template <class Arch>
struct SkinKernel {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  static constexpr std::size_t W = F::size;

  static void morph(const MorphJob& job) {
    for (int c = 0; c < 3; ++c) {
      const float* base = job.base[c];
      float* out = job.out[c];
      if (!base || !out) continue;
      std::size_t i = 0;
      for (; i + W <= job.count; i += W) {
        F v = F::load_unaligned(base + i);
        for (std::size_t t = 0; t < job.target_count; ++t) {
          const float* d = job.targets[t].delta[c];
          if (d) v = v + F(job.targets[t].weight) * F::load_unaligned(d + i);
        }
        v.store_unaligned(out + i);
      }
      for (; i < job.count; ++i) {  // the tail: the same two operations per target
        float v = base[i];
        for (std::size_t t = 0; t < job.target_count; ++t) {
          const float* d = job.targets[t].delta[c];
          if (d) v = v + job.targets[t].weight * d[i];
        }
        out[i] = v;
      }
    }
  }

  // W vertices from `first` (all present): streams loaded directly, joint indices widened in
  // registers, the joints' matrices gathered element by element.
  template <bool Full>
  static void block(const SkinJob& job, std::size_t first) {
    const std::size_t n = job.count, live = Full ? W : n - first;
    // A partial block reads padded copies: lanes past `live` repeat vertex `first`.
    alignas(64) float pad[9][W];
    auto stream = [&](const float* s, float* lanes) -> F {
      if constexpr (Full) return F::load_unaligned(s + first);
      for (std::size_t l = 0; l < W; ++l) lanes[l] = s[first + (l < live ? l : 0)];
      return F::load_aligned(lanes);
    };
    // The blend, one vertex at a time across the matrix's 12 elements (the scalar twin's
    // multiplies and adds, element by element), into `blended`; then element e of the W vertices
    // gathered from there (12 gathers from L1 where gathering each joint's elements took 12 k).
    alignas(64) float blended[W * 16];
    for (std::size_t l = 0; l < W; ++l) {
      const std::size_t v = first + (l < live ? l : 0);
      blend_one(job, v, blended + 16 * l);
    }
    skin_math::Blend<F> b;
    const I rows = I(16) * lane_index();
    const auto* words = reinterpret_cast<const std::int32_t*>(blended);
    for (int e = 0; e < 12; ++e) b.m[e] = xsimd::bitwise_cast<F>(simd_util::gather32<Arch>(words + e, rows));
    F p[3];
    b.point(stream(job.position[0], pad[0]), stream(job.position[1], pad[1]), stream(job.position[2], pad[2]), p);
    store(p, job.out_position, 3, first, live);
    if (job.normal[0] && job.out_normal) {
      F v[3];
      const F x = stream(job.normal[0], pad[3]), y = stream(job.normal[1], pad[4]), z = stream(job.normal[2], pad[5]);
      if (job.normals == NormalTransform::cofactor) b.cofactor(x, y, z, v);
      else b.vector(x, y, z, v);
      skin_math::normalise(v);
      store(v, job.out_normal, 3, first, live);
    }
    if (job.tangent[0] && job.out_tangent) {
      F v[3];
      b.vector(stream(job.tangent[0], pad[6]), stream(job.tangent[1], pad[7]), stream(job.tangent[2], pad[8]), v);
      skin_math::normalise(v);
      store(v, job.out_tangent, 4, first, live);
    }
  }

  static I lane_index() {
    alignas(64) std::int32_t at[W];
    for (std::size_t l = 0; l < W; ++l) at[l] = static_cast<std::int32_t>(l);
    return I::load_aligned(at);
  }

  // out[e] = w0 J0[e], then out[e] = out[e] + wk Jk[e], for the 12 elements of vertex v's joints'
  // 3x4 matrices: the products and sums of skin_math::Blend, in its order, 16, 8 or 4 elements at
  // a time (explicit multiplies and adds: nothing to contract).
  static void blend_one(const SkinJob& job, std::size_t v, float* out) {
    const std::size_t n = job.count;
    const float* m = job.matrices;
    if constexpr (W == 16) {
      const __mmask16 twelve = 0x0fff;
      __m512 acc = _mm512_mul_ps(_mm512_set1_ps(job.weights[v]), _mm512_maskz_loadu_ps(twelve, m + 12 * std::size_t(job.joints[v])));
      for (int k = 1; k < job.influences; ++k) {
        const std::size_t at = std::size_t(k) * n + v;
        acc = _mm512_add_ps(acc, _mm512_mul_ps(_mm512_set1_ps(job.weights[at]), _mm512_maskz_loadu_ps(twelve, m + 12 * std::size_t(job.joints[at]))));
      }
      _mm512_store_ps(out, acc);
    } else if constexpr (W == 8) {
      const float* j = m + 12 * std::size_t(job.joints[v]);
      __m256 w = _mm256_set1_ps(job.weights[v]);
      __m256 lo = _mm256_mul_ps(w, _mm256_loadu_ps(j));
      __m128 hi = _mm_mul_ps(_mm256_castps256_ps128(w), _mm_loadu_ps(j + 8));
      for (int k = 1; k < job.influences; ++k) {
        const std::size_t at = std::size_t(k) * n + v;
        j = m + 12 * std::size_t(job.joints[at]);
        w = _mm256_set1_ps(job.weights[at]);
        lo = _mm256_add_ps(lo, _mm256_mul_ps(w, _mm256_loadu_ps(j)));
        hi = _mm_add_ps(hi, _mm_mul_ps(_mm256_castps256_ps128(w), _mm_loadu_ps(j + 8)));
      }
      _mm256_store_ps(out, lo);
      _mm_store_ps(out + 8, hi);
    } else {
      const float* j = m + 12 * std::size_t(job.joints[v]);
      __m128 w = _mm_set1_ps(job.weights[v]);
      __m128 r0 = _mm_mul_ps(w, _mm_loadu_ps(j)), r1 = _mm_mul_ps(w, _mm_loadu_ps(j + 4)), r2 = _mm_mul_ps(w, _mm_loadu_ps(j + 8));
      for (int k = 1; k < job.influences; ++k) {
        const std::size_t at = std::size_t(k) * n + v;
        j = m + 12 * std::size_t(job.joints[at]);
        w = _mm_set1_ps(job.weights[at]);
        r0 = _mm_add_ps(r0, _mm_mul_ps(w, _mm_loadu_ps(j)));
        r1 = _mm_add_ps(r1, _mm_mul_ps(w, _mm_loadu_ps(j + 4)));
        r2 = _mm_add_ps(r2, _mm_mul_ps(w, _mm_loadu_ps(j + 8)));
      }
      _mm_store_ps(out, r0);
      _mm_store_ps(out + 4, r1);
      _mm_store_ps(out + 8, r2);
    }
  }

  // Lanes into interleaved records of `stride` floats (xyz written, the rest kept).
  static void store(const F* v, float* out, std::size_t stride, std::size_t first, std::size_t live) {
    alignas(64) float lanes[3][W];
    for (int c = 0; c < 3; ++c) v[c].store_aligned(lanes[c]);
    float* o = out + stride * first;
    for (std::size_t l = 0; l < live; ++l, o += stride) o[0] = lanes[0][l], o[1] = lanes[1][l], o[2] = lanes[2][l];
  }

  static void skin(const SkinJob& job) {
    std::size_t i = 0;
    for (; i + W <= job.count; i += W) block<true>(job, i);
    if (i < job.count) block<false>(job, i);
  }
};

}  // namespace
}  // namespace facet::geometry::simd
