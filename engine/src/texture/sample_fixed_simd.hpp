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

  // One level per lane (`level`), nearest or bilinear in 8.8 fixed point; rs, rt wrapped.
  static I level(const Sampler& s, const I& level, bool linear, const F& rs, const F& rt) {
    const typename S::LevelLanes l = S::level_lanes(s, level);
    if (!linear) {
      const I ii = S::fold(xsimd::batch_cast<std::int32_t>(xsimd::floor(rs * l.fw)), l.wi, s.wrap);
      const I jj = S::fold(xsimd::batch_cast<std::int32_t>(xsimd::floor(rt * l.fh)), l.hi, s.wrap);
      return S::texels_at(s, l.base + jj * l.wi + ii);
    }
    const I x = xsimd::batch_cast<std::int32_t>(xsimd::floor(rs * (l.fw * F(256.0f)) - F(127.5f)));
    const I y = xsimd::batch_cast<std::int32_t>(xsimd::floor(rt * (l.fh * F(256.0f)) - F(127.5f)));
    const I i0 = x >> 8, j0 = y >> 8;  // arithmetic shifts: floor(x / 256)
    const I fx = x & I(255), fy = y & I(255);
    const I ia = S::fold_low(i0, l.wi, s.wrap), ib = S::fold_high(i0 + I(1), l.wi, s.wrap);
    const I row_a = l.base + S::fold_low(j0, l.hi, s.wrap) * l.wi;
    const I row_b = l.base + S::fold_high(j0 + I(1), l.hi, s.wrap) * l.wi;
    I t00, t10, t01, t11;
    if (W >= 8 && xsimd::all(ib == ia + I(1))) {  // no lane's columns wrap: adjacent pairs
      S::texel_pairs(s, row_a + ia, t00, t10);
      S::texel_pairs(s, row_b + ia, t01, t11);
    } else {
      t00 = S::texels_at(s, row_a + ia), t10 = S::texels_at(s, row_a + ib);
      t01 = S::texels_at(s, row_b + ia), t11 = S::texels_at(s, row_b + ib);
    }
    return lerp(lerp(t00, t10, fx), lerp(t01, t11, fx), fy);
  }

  // Packed RGBA8 at (u, v) with level of detail lambda (trilinear textures only read it).
  static I sample(const Sampler& s, const F& u, const F& v, const F& lambda) {
    const F rs = S::wrap_coordinate(u, s.wrap), rt = S::wrap_coordinate(v, s.wrap);
    if (s.filter != static_cast<int>(TextureFilter::trilinear)) {
      return level(s, I(0), s.filter != static_cast<int>(TextureFilter::nearest), rs, rt);
    }
    // As the float sampler: lanes with lambda <= 0 (or NaN) magnify from level 0, lanes at or past
    // the last level q read it alone (weight 0: the lerp returns the first level's bytes).
    const int q = s.levels - 1;
    const auto minify = lambda > F(0.0f);
    const F l = xsimd::select(lambda < F(static_cast<float>(q)), lambda, F(static_cast<float>(q)));
    const F d1 = xsimd::select(minify, xsimd::floor(l), F(0.0f));
    const I k = xsimd::batch_cast<std::int32_t>(d1);
    const auto single = (!minify) | (d1 >= F(static_cast<float>(q)));
    const I w = xsimd::select(xsimd::bool_cast(single), I(0), xsimd::batch_cast<std::int32_t>((l - d1) * F(256.0f)));
    const I c1 = level(s, k, true, rs, rt);
    if (xsimd::all(w == I(0))) return c1;
    const I next = xsimd::select(k >= I(q), k, k + I(1));
    return lerp(c1, level(s, next, true, rs, rt), w);
  }

  // `count` samples from planar inputs (u, v, ds/dx, dt/dx, ds/dy, dt/dy) to packed RGBA8, W at a
  // time (the LOD as the float sampler computes it).
  static void sample_streams(const Sampler& s, std::size_t count, const float* const* in, std::uint32_t* out) {
    for (std::size_t i = 0; i < count; i += static_cast<std::size_t>(W)) {
      const std::size_t n = count - i < static_cast<std::size_t>(W) ? count - i : static_cast<std::size_t>(W);
      alignas(64) float lanes[6][W] = {};
      for (int k = 0; k < 6; ++k)
        for (std::size_t j = 0; j < n; ++j) lanes[k][j] = in[k][i + j];
      const F lambda = S::lod(s, F::load_aligned(lanes[2]), F::load_aligned(lanes[3]), F::load_aligned(lanes[4]),
                              F::load_aligned(lanes[5]));
      alignas(64) std::int32_t result[W];
      sample(s, F::load_aligned(lanes[0]), F::load_aligned(lanes[1]), lambda).store_aligned(result);
      for (std::size_t j = 0; j < n; ++j) out[i + j] = static_cast<std::uint32_t>(result[j]);
    }
  }
};

}  // namespace
}  // namespace facet::texture::simd
