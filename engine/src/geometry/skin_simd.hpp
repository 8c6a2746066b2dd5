// Internal: the morph and skinning kernels (skin.hpp) W vertices at a time, a template on the
// xsimd architecture, included only by skin_{sse2,avx2,avx512}.cpp (each compiled with its ISA's
// flags and -ffp-contract=off). The arithmetic is skin_math.hpp's, as in the scalar twin; the
// joint matrices are gathered per lane (hardware gathers on avx2 and avx512); the tail of fewer
// than W vertices runs through the same batch code on padded copies.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

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

  // W vertices from `first`: lanes past `count` read vertex `first` again and are not stored.
  static void block(const SkinJob& job, std::size_t first) {
    const std::size_t n = job.count, live = std::min(W, n - first);
    alignas(64) std::int32_t index[W];
    alignas(64) float in[9][W], w[W];
    auto load = [&](const float* s, float* lanes) {
      for (std::size_t l = 0; l < W; ++l) lanes[l] = s[first + (l < live ? l : 0)];
    };
    skin_math::Blend<F> b;
    const auto* matrices = reinterpret_cast<const std::int32_t*>(job.matrices);
    for (int k = 0; k < job.influences; ++k) {
      const std::uint16_t* jk = job.joints + std::size_t(k) * n;
      for (std::size_t l = 0; l < W; ++l) index[l] = 12 * std::int32_t(jk[first + (l < live ? l : 0)]);
      load(job.weights + std::size_t(k) * n, w);
      const I at = I::load_aligned(index);
      F j[12];
      for (int e = 0; e < 12; ++e) j[e] = xsimd::bitwise_cast<F>(simd_util::gather32<Arch>(matrices + e, at));
      const F wk = F::load_aligned(w);
      if (k == 0) b.first(wk, j);
      else b.add(wk, j);
    }
    for (int c = 0; c < 3; ++c) load(job.position[c], in[c]);
    F p[3];
    b.point(F::load_aligned(in[0]), F::load_aligned(in[1]), F::load_aligned(in[2]), p);
    store(p, job.out_position, 3, first, live);
    if (job.normal[0] && job.out_normal) {
      for (int c = 0; c < 3; ++c) load(job.normal[c], in[3 + c]);
      F v[3];
      const F x = F::load_aligned(in[3]), y = F::load_aligned(in[4]), z = F::load_aligned(in[5]);
      if (job.normals == NormalTransform::cofactor) b.cofactor(x, y, z, v);
      else b.vector(x, y, z, v);
      skin_math::normalise(v);
      store(v, job.out_normal, 3, first, live);
    }
    if (job.tangent[0] && job.out_tangent) {
      for (int c = 0; c < 3; ++c) load(job.tangent[c], in[6 + c]);
      F v[3];
      b.vector(F::load_aligned(in[6]), F::load_aligned(in[7]), F::load_aligned(in[8]), v);
      skin_math::normalise(v);
      store(v, job.out_tangent, 4, first, live);
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
    for (std::size_t i = 0; i < job.count; i += W) block(job, i);
  }
};

}  // namespace
}  // namespace facet::geometry::simd
