// Internal: the fixed-point sampler of the 16-bit pixel tier, a template on the xsimd architecture:
// the twin of sample_fixed_scalar (sampler.cpp; the arithmetic is described in sampler.hpp), bit
// for bit. Coordinates, levels and wrapping are the float sampler's (SampleSimd, whose helpers it
// calls); the filter works on packed RGBA8 texels, two bytes at a time per 32-bit lane: masked to
// 0x00ff00ff, each 16-bit half holds one channel, and a 16-bit multiply by the weight (<= 256)
// gives each half's product (<= 255 x 256, so a lerp's sum plus its rounding, <= 65408, never
// carries into the next half). Included only by the per-ISA raster files (built with
// -ffp-contract=off); templates only.
#pragma once

#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "texture/sample_simd.hpp"
#include "texture/sampler.hpp"

namespace facet::texture::simd {
namespace {

template <class Arch>
struct SampleFixed {
  using S = SampleSimd<Arch>;
  using F = typename S::F;
  using I = typename S::I;
  using U = typename S::U;
  using H = xsimd::batch<std::uint16_t, Arch>;
  static constexpr int W = S::W;

  // Per byte of two packed texels a and b: (a (256 - w) + b w + 128) >> 8, w in [0, 256] per lane.
  static I lerp(const I& a, const I& b, const I& w) {
    const U mask(0x00ff00ffu);
    const U wp = xsimd::bitwise_cast<U>(w) | (xsimd::bitwise_cast<U>(w) << 16);  // w in both halves
    const U vp = U(0x01000100u) - wp;                                              // 256 - w in both halves
    auto mul = [](const U& x, const U& y) {
      return xsimd::bitwise_cast<U>(xsimd::bitwise_cast<H>(x) * xsimd::bitwise_cast<H>(y));
    };
    const U ua = xsimd::bitwise_cast<U>(a), ub = xsimd::bitwise_cast<U>(b);
    const U rb = mul(ua & mask, vp) + mul(ub & mask, wp) + U(0x00800080u);
    const U ag = mul((ua >> 8) & mask, vp) + mul((ub >> 8) & mask, wp) + U(0x00800080u);
    return xsimd::bitwise_cast<I>(((rb >> 8) & mask) | (ag & U(0xff00ff00u)));
  }

  // One level per lane (`level`), nearest or bilinear in 8.8 fixed point, for P batches at once
  // (each step for every batch before the next, so two independent chains overlap, as the float
  // sampler does); rs, rt wrapped.
  template <int P>
  [[gnu::always_inline]] inline static void levels(const Sampler& s, const I (&level)[P], bool linear, const F (&rs)[P],
                                                   const F (&rt)[P], I (&out)[P]) {
    typename S::LevelLanes l[P];
    for (int p = 0; p < P; ++p) l[p] = S::level_lanes(s, level[p]);
    if (!linear) {
      for (int p = 0; p < P; ++p) {
        const I ii = S::fold(xsimd::batch_cast<std::int32_t>(xsimd::floor(rs[p] * l[p].fw)), l[p].wi, s.wrap);
        const I jj = S::fold(xsimd::batch_cast<std::int32_t>(xsimd::floor(rt[p] * l[p].fh)), l[p].hi, s.wrap);
        out[p] = S::texels_at(s, l[p].base + jj * l[p].wi + ii);
      }
      return;
    }
    I fx[P], fy[P], t00[P], t10[P], t01[P], t11[P];
    for (int p = 0; p < P; ++p) {
      const I x = xsimd::batch_cast<std::int32_t>(xsimd::floor(rs[p] * (l[p].fw * F(256.0f)) - F(127.5f)));
      const I y = xsimd::batch_cast<std::int32_t>(xsimd::floor(rt[p] * (l[p].fh * F(256.0f)) - F(127.5f)));
      const I i0 = x >> 8, j0 = y >> 8;  // arithmetic shifts: floor(x / 256)
      fx[p] = x & I(255), fy[p] = y & I(255);
      const I ia = S::fold_low(i0, l[p].wi, s.wrap), ib = S::fold_high(i0 + I(1), l[p].wi, s.wrap);
      const I row_a = l[p].base + S::fold_low(j0, l[p].hi, s.wrap) * l[p].wi;
      const I row_b = l[p].base + S::fold_high(j0 + I(1), l[p].hi, s.wrap) * l[p].wi;
      if (W >= 8 && xsimd::all(ib == ia + I(1))) {  // no lane's columns wrap: adjacent pairs
        S::texel_pairs(s, row_a + ia, t00[p], t10[p]);
        S::texel_pairs(s, row_b + ia, t01[p], t11[p]);
      } else {
        t00[p] = S::texels_at(s, row_a + ia), t10[p] = S::texels_at(s, row_a + ib);
        t01[p] = S::texels_at(s, row_b + ia), t11[p] = S::texels_at(s, row_b + ib);
      }
    }
    for (int p = 0; p < P; ++p) out[p] = lerp(lerp(t00[p], t10[p], fx[p]), lerp(t01[p], t11[p], fx[p]), fy[p]);
  }
  static I level(const Sampler& s, const I& level, bool linear, const F& rs, const F& rt) {
    I out[1];
    levels<1>(s, {level}, linear, {rs}, {rt}, out);
    return out[0];
  }

  // Packed RGBA8 at (u, v) with level of detail lambda (trilinear textures only read it), for P
  // batches. `guess` (may be null) as the float sampler's (SampleSimd::sample): the levels the
  // previous batches read are sampled while the LOD is turned into levels, and kept when every
  // lane's levels are the guessed ones; otherwise sampled again. The same operations on the same
  // levels, so the same bytes.
  template <int P>
  [[gnu::always_inline]] inline static void sample(const Sampler& s, const F (&u)[P], const F (&v)[P],
                                                   const F (&lambda)[P], I (&out)[P], int* guess = nullptr) {
    constexpr int kOne = S::kGuessOneLevel;
    F rs[P], rt[P];
    for (int p = 0; p < P; ++p) rs[p] = S::wrap_coordinate(u[p], s.wrap), rt[p] = S::wrap_coordinate(v[p], s.wrap);
    if (s.filter != static_cast<int>(TextureFilter::trilinear)) {
      I zero[P];
      for (int p = 0; p < P; ++p) zero[p] = I(0);
      levels<P>(s, zero, s.filter != static_cast<int>(TextureFilter::nearest), rs, rt, out);
      return;
    }
    // As the float sampler: lanes with lambda <= 0 (or NaN) magnify from level 0, lanes at or past
    // the last level q read it alone (weight 0: the lerp returns the first level's bytes).
    const int q = s.levels - 1;
    const bool guessed = guess && *guess >= 0;
    const bool one_level = guessed && (*guess & kOne);
    const int guessed_level = guessed ? *guess & (kOne - 1) : 0;
    const int g = guessed_level < q ? guessed_level : q;
    I c1[P], c2[P];
    for (int p = 0; p < P; ++p) c1[p] = c2[p] = I(0);  // each is read only after a sample wrote it
    if (guessed) {
      I kg[P], ng[P];
      for (int p = 0; p < P; ++p) kg[p] = I(g), ng[p] = I(g < q ? g + 1 : g);
      levels<P>(s, kg, true, rs, rt, c1);
      if (!one_level) levels<P>(s, ng, true, rs, rt, c2);
    }
    I k[P], next[P], w[P];
    bool second = false, hit = guessed;
    for (int p = 0; p < P; ++p) {
      const typename S::LevelChoice c = S::choose_levels(lambda[p], q);  // the float sampler's levels
      k[p] = c.k, next[p] = c.next;
      w[p] = xsimd::select(xsimd::bool_cast(c.single), I(0), xsimd::batch_cast<std::int32_t>(c.fraction * F(256.0f)));
      second = second || xsimd::any(w[p] != I(0));
      hit = hit && xsimd::all(k[p] == I(g));
    }
    // A hit read k and next (= k + 1, or k at the last level); a one-level hit read k alone,
    // which serves only when no lane needs a second level.
    if (one_level && second) hit = false;
    if (!hit) {
      levels<P>(s, k, true, rs, rt, c1);
      if (second) levels<P>(s, next, true, rs, rt, c2);
      if (guess) *guess = k[0].get(0) | (second ? 0 : kOne);
    } else if (!second && !one_level) {
      *guess |= kOne;  // the next batches may read one level
    }
    for (int p = 0; p < P; ++p) out[p] = second ? lerp(c1[p], c2[p], w[p]) : c1[p];
  }
  static I sample(const Sampler& s, const F& u, const F& v, const F& lambda) {
    I out[1];
    sample<1>(s, {u}, {v}, {lambda}, out);
    return out[0];
  }

  // `count` samples from planar inputs (u, v, ds/dx, dt/dx, ds/dy, dt/dy) to packed RGBA8, two
  // batches at a time with a level guess carried along (the last batch alone), as a program
  // samples; the LOD as the float sampler computes it.
  static void sample_streams(const Sampler& s, std::size_t count, const float* const* in, std::uint32_t* out) {
    int guess = -1;
    for (std::size_t i = 0; i < count; i += static_cast<std::size_t>(2 * W)) {
      alignas(64) float lanes[2][6][W] = {};
      std::size_t n[2];
      for (int p = 0; p < 2; ++p) {
        const std::size_t from = i + static_cast<std::size_t>(p * W);
        n[p] = from >= count ? 0 : (count - from < static_cast<std::size_t>(W) ? count - from : static_cast<std::size_t>(W));
        for (int k = 0; k < 6; ++k)
          for (std::size_t j = 0; j < n[p]; ++j) lanes[p][k][j] = in[k][from + j];
      }
      F u[2], v[2], lambda[2];
      for (int p = 0; p < 2; ++p) {
        u[p] = F::load_aligned(lanes[p][0]), v[p] = F::load_aligned(lanes[p][1]);
        lambda[p] = S::lod(s, F::load_aligned(lanes[p][2]), F::load_aligned(lanes[p][3]), F::load_aligned(lanes[p][4]),
                           F::load_aligned(lanes[p][5]));
      }
      I texel[2];
      if (n[1] > 0) {
        sample<2>(s, u, v, lambda, texel, &guess);
      } else {
        I one[1];
        sample<1>(s, {u[0]}, {v[0]}, {lambda[0]}, one, &guess);
        texel[0] = one[0];
      }
      for (int p = 0; p < 2; ++p) {
        alignas(64) std::int32_t result[W];
        texel[p].store_aligned(result);
        for (std::size_t j = 0; j < n[p]; ++j) out[i + static_cast<std::size_t>(p * W) + j] = static_cast<std::uint32_t>(result[j]);
      }
    }
  }
};

}  // namespace
}  // namespace facet::texture::simd
