// Internal: the SIMD texture sampler, a template on the xsimd architecture: the twin of
// sample_scalar (sampler.cpp), the same IEEE float operations in the same order, with coordinates,
// weights, LOD and filtering in SIMD lanes and the texel fetches per lane (the levels of a
// trilinear sample may differ from lane to lane). Included only by the per-ISA raster files, each
// compiled with -ffp-contract=off; everything is a template or in an unnamed namespace (an inline
// function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
#pragma once

#include <cfloat>
#include <cstdint>

#include <immintrin.h>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "common/gather_simd.hpp"
#include "texture/sampler.hpp"

namespace facet::texture::simd {
namespace {

template <class Arch>
struct SampleSimd {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using U = xsimd::batch<std::uint32_t, Arch>;
  static constexpr int W = static_cast<int>(F::size);

  static F wrap_coordinate(const F& s, int wrap) {
    if (wrap == static_cast<int>(TextureWrap::repeat)) {
      const F r = s - xsimd::floor(s);
      return xsimd::select((r >= F(0.0f)) & (r < F(1.0f)), r, F(0.0f));
    }
    if (wrap == static_cast<int>(TextureWrap::mirror)) {
      const F r = s - F(2.0f) * xsimd::floor(s * F(0.5f));
      return xsimd::select((r >= F(0.0f)) & (r < F(2.0f)), r, F(0.0f));
    }
    return xsimd::select(s > F(0.0f), xsimd::select(s < F(1.0f), s, F(1.0f)), F(0.0f));
  }

  static I fold(I i, const I& n, int wrap) {
    if (wrap == static_cast<int>(TextureWrap::repeat)) {
      i = xsimd::select(i < I(0), i + n, i);
      return xsimd::select(i >= n, i - n, i);
    }
    if (wrap == static_cast<int>(TextureWrap::mirror)) {
      const I two_n = n + n;
      i = xsimd::select(i < I(0), i + two_n, i);
      i = xsimd::select(i >= two_n, i - two_n, i);
      return xsimd::select(i >= n, two_n - I(1) - i, i);
    }
    return xsimd::select(i < I(0), I(0), xsimd::select(i >= n, n - I(1), i));
  }
  // fold() for the two texel columns (or rows) of a linear sample, whose ranges the wrapped
  // coordinate bounds (r n rounds to at most n for r < 1, 2n for r < 2): i0 in [-1, n - 1]
  // ([-1, 2n - 1] mirrored) can only be low, i0 + 1 in [0, n] ([0, 2n]) only high. The same
  // results as fold() on those ranges, with half its selects.
  static I fold_low(const I& i, const I& n, int wrap) {
    if (wrap == static_cast<int>(TextureWrap::repeat)) return xsimd::select(i < I(0), i + n, i);
    if (wrap == static_cast<int>(TextureWrap::mirror)) {
      const I two_n = n + n;
      const I j = xsimd::select(i < I(0), i + two_n, i);
      return xsimd::select(j >= n, two_n - I(1) - j, j);
    }
    return xsimd::max(i, I(0));
  }
  static I fold_high(const I& i, const I& n, int wrap) {
    if (wrap == static_cast<int>(TextureWrap::repeat)) return xsimd::select(i >= n, i - n, i);
    if (wrap == static_cast<int>(TextureWrap::mirror)) {
      const I two_n = n + n;
      const I j = xsimd::select(i >= two_n, i - two_n, i);
      return xsimd::select(j >= n, two_n - I(1) - j, j);
    }
    return xsimd::min(i, n - I(1));
  }

  // Channel c (0..3) of RGBA8 texels as floats 0..255, the same integers as (texel >> 8c) & 255:
  // R masked, A shifted down logically, G and B moved to the low byte by one byte shuffle where the
  // ISA has one (avx2, avx512bw; it indexes within 128-bit lanes, dword k's bytes are 4k..4k+3,
  // and 0x80 writes zero).
  // A template on c: every caller's channel loop runs four times with c a constant, so the
  // shuffle masks are constants (a loop over a runtime c built them per batch on avx2).
  template <int c>
  static F channel(const I& texel) {
    if constexpr (c == 0) {
      return xsimd::batch_cast<float>(texel & I(0xff));
    } else if constexpr (c == 3) {
      return xsimd::batch_cast<float>(xsimd::bitwise_cast<I>(xsimd::bitwise_cast<U>(texel) >> 24));
    } else {
      constexpr int b0 = static_cast<int>(0x80808000u) | c;
      if constexpr (W == 16) {
        return xsimd::batch_cast<float>(I(_mm512_shuffle_epi8(texel, _mm512_set4_epi32(b0 | 12, b0 | 8, b0 | 4, b0))));
      } else if constexpr (W == 8) {
        return xsimd::batch_cast<float>(I(_mm256_shuffle_epi8(
            texel, _mm256_set_epi32(b0 | 12, b0 | 8, b0 | 4, b0, b0 | 12, b0 | 8, b0 | 4, b0))));
      } else {
        return xsimd::batch_cast<float>((texel >> (8 * c)) & I(0xff));
      }
    }
  }
  // channel<c>, or for the colour channels of an sRGB texture 255 x their decoding, gathered from
  // the sampler's table (the scalar twin reads the same floats).
  template <int c>
  static F value(const Sampler& s, const I& texel) {
    if constexpr (c < 3) {
      if (s.decode) return gather(s.decode, (texel >> (8 * c)) & I(0xff));
    }
    return channel<c>(texel);
  }
  // f(std::integral_constant<int, c>) for c = 0, 1, 2, 3 (the callee reads c as a constant).
  template <class Fn>
  static void each_channel(Fn&& f) {
    f(std::integral_constant<int, 0>{}), f(std::integral_constant<int, 1>{});
    f(std::integral_constant<int, 2>{}), f(std::integral_constant<int, 3>{});
  }

  static F log2_approx(const F& x) {
    const I bits = xsimd::bitwise_cast<I>(x);
    const I e = ((bits >> 23) & I(0xff)) - I(127);
    const F m = xsimd::bitwise_cast<F>((bits & I(0x7fffff)) | I(0x3f800000)) - F(1.0f);
    F p(kLog2Poly[4]);
    p = p * m + F(kLog2Poly[3]);
    p = p * m + F(kLog2Poly[2]);
    p = p * m + F(kLog2Poly[1]);
    p = p * m + F(kLog2Poly[0]);
    return xsimd::batch_cast<float>(e) + p * m;
  }

  static F lod(const Sampler& s, const F& dsdx, const F& dtdx, const F& dsdy, const F& dtdy) {
    const F ax = dsdx * F(s.lod_width), bx = dtdx * F(s.lod_height);
    const F ay = dsdy * F(s.lod_width), by = dtdy * F(s.lod_height);
    const F px = ax * ax + bx * bx, py = ay * ay + by * by;
    const F rho2 = xsimd::select(px > py, px, py);
    const auto magnify = !(rho2 >= F(FLT_MIN));
    const F safe = xsimd::select(magnify | (rho2 > F(FLT_MAX)), F(1.0f), rho2);
    const F lambda = F(0.5f) * log2_approx(safe);
    return xsimd::select(magnify, F(-1.0f), xsimd::select(rho2 > F(FLT_MAX), F(kFarLod), lambda));
  }

  // Level `level` (per lane) of each lane, nearest or bilinear: RGBA in out[0..3]. The level's
  // size and the texels come from the Sampler's tables with gathers (avx2 and avx512 have them;
  // xsimd emulates them on sse2): the same integers as the scalar twin's per-lane reads.
  static I gather(const std::int32_t* base, const I& index) {
    return simd_util::gather32<typename F::arch_type>(base, index);
  }
  static F gather(const float* base, const I& index) {
    return xsimd::bitwise_cast<F>(gather(reinterpret_cast<const std::int32_t*>(base), index));
  }
  static I texels_at(const Sampler& s, const I& index) {
    return gather(reinterpret_cast<const std::int32_t*>(s.texels), index);
  }
  // The texels at index and index + 1 of each lane (both in one row of the level) as one 64-bit
  // element: two gathers of W / 2 64-bit elements and two permutes instead of two gathers of W
  // 32-bit elements (a gather's cost grows with its element count, not its width). The same
  // texels, so the same bits.
  static void texel_pairs(const Sampler& s, const I& index, I& first, I& second) {
    if constexpr (W == 16) {
      const auto* base = reinterpret_cast<const long long*>(s.texels);
      const __m512i lo = _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), __mmask8(0xff),
                                                     _mm512_castsi512_si256(index), base, 4);
      const __m512i hi = _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), __mmask8(0xff),
                                                     _mm512_extracti64x4_epi64(index, 1), base, 4);
      const __m512i even = _mm512_set_epi32(30, 28, 26, 24, 22, 20, 18, 16, 14, 12, 10, 8, 6, 4, 2, 0);
      first = I(_mm512_permutex2var_epi32(lo, even, hi));
      second = I(_mm512_permutex2var_epi32(lo, _mm512_add_epi32(even, _mm512_set1_epi32(1)), hi));
    } else if constexpr (W == 8) {
      const auto* base = reinterpret_cast<const long long*>(s.texels);
      const __m256i lo = _mm256_i32gather_epi64(base, _mm256_castsi256_si128(index), 4);
      const __m256i hi = _mm256_i32gather_epi64(base, _mm256_extracti128_si256(index, 1), 4);
      // Per 128-bit half: the first (second) dwords of lo's two elements, then hi's; then the
      // halves' 64-bit parts in order 0, 2, 1, 3.
      const __m256 l = _mm256_castsi256_ps(lo), h = _mm256_castsi256_ps(hi);
      first = I(_mm256_permute4x64_epi64(_mm256_castps_si256(_mm256_shuffle_ps(l, h, 0x88)), 0xd8));
      second = I(_mm256_permute4x64_epi64(_mm256_castps_si256(_mm256_shuffle_ps(l, h, 0xdd)), 0xd8));
    } else {
      first = texels_at(s, index), second = texels_at(s, index + I(1));
    }
  }
  // The level's size and first texel per lane: broadcast when every lane reads the same level
  // (the common case: a level changes over many pixels), gathered otherwise.
  struct LevelLanes {
    I wi, hi, base;
    F fw, fh;
  };
  static LevelLanes level_lanes(const Sampler& s, const I& level) {
    const std::int32_t k = level.get(0);
    if (xsimd::all(level == I(k))) {
      return {I(s.width[k]), I(s.height[k]), I(s.offset[k]), F(s.fwidth[k]), F(s.fheight[k])};
    }
    return {gather(s.width, level), gather(s.height, level), gather(s.offset, level), gather(s.fwidth, level),
            gather(s.fheight, level)};
  }
  // The sampler works on P batches of lanes at once (1 or 2): each step for every batch before the
  // next step, the same operations on each as on one. A trilinear sample is a chain of a few
  // hundred dependent cycles (LOD, level, coordinates, gathers, filter) longer than the core's
  // reordering window, so a second independent chain in the same window keeps it busy while the
  // first waits.
  //
  // rs, rt: the coordinates wrapped (wrap_coordinate), once for both levels of a trilinear sample.
  //
  // Inlined into sample() on avx512 and called on the narrower ISAs: each measured faster that way
  // (alternated runs of the textured fill).
  template <int P>
  [[gnu::always_inline]] inline static void sample_levels(const Sampler& s, const I (&level)[P], bool linear,
                                                          const F (&rs)[P], const F (&rt)[P], F (&out)[P][4]) {
    if constexpr (W == 16) {
      filter_levels<P>(s, level, linear, rs, rt, out);
    } else {
      filter_levels_call<P>(s, level, linear, rs, rt, out);
    }
  }
  template <int P>
  [[gnu::noinline]] static void filter_levels_call(const Sampler& s, const I (&level)[P], bool linear,
                                                   const F (&rs)[P], const F (&rt)[P], F (&out)[P][4]) {
    filter_levels<P>(s, level, linear, rs, rt, out);
  }
  template <int P>
  [[gnu::always_inline]] inline static void filter_levels(const Sampler& s, const I (&level)[P], bool linear,
                                                          const F (&rs)[P], const F (&rt)[P], F (&out)[P][4]) {
    LevelLanes lanes[P];
    for (int p = 0; p < P; ++p) lanes[p] = level_lanes(s, level[p]);
    if (!linear) {
      for (int p = 0; p < P; ++p) {
        const LevelLanes& l = lanes[p];
        const I ii = fold(xsimd::batch_cast<std::int32_t>(xsimd::floor(rs[p] * l.fw)), l.wi, s.wrap);
        const I jj = fold(xsimd::batch_cast<std::int32_t>(xsimd::floor(rt[p] * l.fh)), l.hi, s.wrap);
        const I t00 = texels_at(s, l.base + jj * l.wi + ii);
        each_channel([&](auto c) {
          constexpr int k = decltype(c)::value;
          out[p][k] = value<k>(s, t00) * F(1.0f / 255.0f);
        });
      }
      return;
    }
    F a[P], b[P];
    I t00[P], t10[P], t01[P], t11[P];
    for (int p = 0; p < P; ++p) {
      const LevelLanes& l = lanes[p];
      const F x = rs[p] * l.fw - F(0.5f), y = rt[p] * l.fh - F(0.5f);
      const F fx = xsimd::floor(x), fy = xsimd::floor(y);
      a[p] = x - fx, b[p] = y - fy;
      const I i0 = xsimd::batch_cast<std::int32_t>(fx), j0 = xsimd::batch_cast<std::int32_t>(fy);
      const I ia = fold_low(i0, l.wi, s.wrap), ib = fold_high(i0 + I(1), l.wi, s.wrap);
      const I row_a = l.base + fold_low(j0, l.hi, s.wrap) * l.wi;
      const I row_b = l.base + fold_high(j0 + I(1), l.hi, s.wrap) * l.wi;
      if constexpr (W >= 8) {
        if (xsimd::all(ib == ia + I(1))) {  // no lane's columns wrap: each pair is two adjacent texels
          texel_pairs(s, row_a + ia, t00[p], t10[p]);
          texel_pairs(s, row_b + ia, t01[p], t11[p]);
          continue;
        }
      }
      t00[p] = texels_at(s, row_a + ia), t10[p] = texels_at(s, row_a + ib);
      t01[p] = texels_at(s, row_b + ia), t11[p] = texels_at(s, row_b + ib);
    }
    for (int p = 0; p < P; ++p) {
      const F ra = F(1.0f) - a[p], rb = F(1.0f) - b[p];
      each_channel([&](auto c) {
        constexpr int k = decltype(c)::value;
        const F top = value<k>(s, t00[p]) * ra + value<k>(s, t10[p]) * a[p];
        const F bottom = value<k>(s, t01[p]) * ra + value<k>(s, t11[p]) * a[p];
        out[p][k] = (top * rb + bottom * b[p]) * F(1.0f / 255.0f);
      });
    }
  }

  // The levels a trilinear sample at LOD lambda reads, q being the last level: k (lanes with
  // lambda <= 0, or NaN, magnify from level 0), next = k + 1 (k at the last level), the fraction
  // l - k towards next, and `single`, the lanes that read k alone (magnified, or at or past the
  // last level). The float and the fixed-point samplers' one rule (each weighs the fraction in its
  // own number format).
  struct LevelChoice {
    I k, next;
    F fraction;
    xsimd::batch_bool<float, Arch> single;
  };
  [[gnu::always_inline]] inline static LevelChoice choose_levels(const F& lambda, int q) {
    const auto minify = lambda > F(0.0f);
    const F l = xsimd::select(lambda < F(static_cast<float>(q)), lambda, F(static_cast<float>(q)));
    const F d1 = xsimd::select(minify, xsimd::floor(l), F(0.0f));
    LevelChoice c;
    c.k = xsimd::batch_cast<std::int32_t>(d1);
    c.single = (!minify) | (d1 >= F(static_cast<float>(q)));
    c.fraction = l - d1;
    c.next = xsimd::select(c.k >= I(q), c.k, c.k + I(1));
    return c;
  }

  // RGBA at (u, v) with level of detail lambda (used only by trilinear textures), for P batches.
  //
  // guess (may be null): a trilinear sample's levels depend on its LOD, a chain of about 70
  // dependent cycles (derivatives, log2, level, the level's size) before the texel coordinates
  // can start. A guess (*guess < 0: none) is what the previous batches read: their first lane's
  // level, plus kGuessOneLevel when no lane read a second level (magnified, at the last level).
  // The guessed level (and the next, unless one level was read) is sampled while the LOD is
  // computed, and kept when every lane's level is the guess (the usual case: the level changes
  // over many pixels) and, for a one-level guess, no lane needs a second level; otherwise the
  // levels are sampled again with the real ones. Kept samples are the same operations on the
  // same levels, so the same bits.
  //
  // sample_inline: the same, always inlined (for the fused modulate program of the narrower ISAs,
  // pixel/programs_simd.hpp, where out of line it measured slower).
  static constexpr int kGuessOneLevel = 0x100;
  template <int P>
  static void sample(const Sampler& s, const F (&u)[P], const F (&v)[P], const F (&lambda)[P], F (&out)[P][4],
                     int* guess = nullptr) {
    sample_inline<P>(s, u, v, lambda, out, guess);
  }
  template <int P>
  [[gnu::always_inline]] inline static void sample_inline(const Sampler& s, const F (&u)[P], const F (&v)[P],
                                                         const F (&lambda)[P], F (&out)[P][4], int* guess) {
    F rs[P], rt[P];
    for (int p = 0; p < P; ++p) rs[p] = wrap_coordinate(u[p], s.wrap), rt[p] = wrap_coordinate(v[p], s.wrap);
    if (s.filter != static_cast<int>(TextureFilter::trilinear)) {
      I zero[P];
      for (int p = 0; p < P; ++p) zero[p] = I(0);
      sample_levels<P>(s, zero, s.filter != static_cast<int>(TextureFilter::nearest), rs, rt, out);
      return;
    }
    // Lanes with lambda <= 0 (or NaN) magnify from level 0; lanes at or past the last level q
    // read it alone (f = 0: c1 * 1 + c2 * 0 is c1 exactly, as the scalar twin returns it; the
    // second level is read when any lane of any batch needs it, and is then multiplied by 0
    // where f is 0: c2 is finite, so the sum is still c1 exactly).
    const int q = s.levels - 1;
    F c1[P][4], c2[P][4];
    const bool guessed = guess && *guess >= 0;
    const bool one_level = guessed && (*guess & kGuessOneLevel);
    const int guessed_level = guessed ? *guess & (kGuessOneLevel - 1) : 0;
    const int g = guessed_level < q ? guessed_level : q;  // the guessed level (when guessed)
    if (guessed) {
      I kg[P];
      for (int p = 0; p < P; ++p) kg[p] = I(g);
      sample_levels<P>(s, kg, true, rs, rt, c1);
      if (one_level) {
        for (int p = 0; p < P; ++p)
          for (int c = 0; c < 4; ++c) c2[p][c] = F(0.0f);
      } else {
        I ng[P];
        for (int p = 0; p < P; ++p) ng[p] = I(g < q ? g + 1 : g);
        sample_levels<P>(s, ng, true, rs, rt, c2);
      }
    }
    I k[P], next[P];
    F f[P];
    bool second = false, hit = guessed;
    for (int p = 0; p < P; ++p) {
      const LevelChoice c = choose_levels(lambda[p], q);
      k[p] = c.k, next[p] = c.next;
      f[p] = xsimd::select(c.single, F(0.0f), c.fraction);
      second = second || xsimd::any(f[p] != F(0.0f));
      hit = hit && xsimd::all(k[p] == I(g));
    }
    // A hit read k and next (= k + 1, or k at the last level), and c2 is finite where f is 0; or
    // a one-level hit read k, and c2 is 0 as below.
    if (one_level && second) hit = false;
    if (!hit) {
      sample_levels<P>(s, k, true, rs, rt, c1);
      if (second) {
        sample_levels<P>(s, next, true, rs, rt, c2);
      } else {
        for (int p = 0; p < P; ++p)
          for (int c = 0; c < 4; ++c) c2[p][c] = F(0.0f);
      }
      if (guess) *guess = k[0].get(0) | (second ? 0 : kGuessOneLevel);
    } else if (!second && !one_level) {
      *guess |= kGuessOneLevel;  // the next batches may read one level
    }
    for (int p = 0; p < P; ++p)
      for (int c = 0; c < 4; ++c) out[p][c] = c1[p][c] * (F(1.0f) - f[p]) + c2[p][c] * f[p];
  }
  static void sample(const Sampler& s, const F& u, const F& v, const F& lambda, F* out) {
    F rgba[1][4];
    sample<1>(s, {u}, {v}, {lambda}, rgba);
    for (int c = 0; c < 4; ++c) out[c] = rgba[0][c];
  }

  // `count` samples from planar inputs (u, v, ds/dx, dt/dx, ds/dy, dt/dy) to planar RGBA: two
  // batches at a time (the last alone when their number is odd), as the rasterizer samples.
  static void sample_streams(const Sampler& s, std::size_t count, const float* const* in, float* const* out) {
    for (std::size_t i = 0; i < count;) {
      const std::size_t left = count - i;
      if (left > static_cast<std::size_t>(W)) {
        sample_some<2>(s, i, left, in, out);
        i += left < static_cast<std::size_t>(2 * W) ? left : static_cast<std::size_t>(2 * W);
      } else {
        sample_some<1>(s, i, left, in, out);
        i = count;
      }
    }
  }
  template <int P>
  static void sample_some(const Sampler& s, std::size_t i, std::size_t left, const float* const* in, float* const* out) {
    alignas(64) float lanes[P][6][W] = {};
    std::size_t n[P];
    for (int p = 0; p < P; ++p) {
      const std::size_t from = static_cast<std::size_t>(p * W);
      n[p] = left <= from ? 0 : (left - from < static_cast<std::size_t>(W) ? left - from : static_cast<std::size_t>(W));
      for (int k = 0; k < 6; ++k)
        for (std::size_t l = 0; l < n[p]; ++l) lanes[p][k][l] = in[k][i + from + l];
    }
    F u[P], v[P], lambda[P], rgba[P][4];
    for (int p = 0; p < P; ++p) {
      u[p] = F::load_aligned(lanes[p][0]), v[p] = F::load_aligned(lanes[p][1]);
      lambda[p] = lod(s, F::load_aligned(lanes[p][2]), F::load_aligned(lanes[p][3]), F::load_aligned(lanes[p][4]),
                      F::load_aligned(lanes[p][5]));
    }
    sample<P>(s, u, v, lambda, rgba);
    for (int p = 0; p < P; ++p) {
      alignas(64) float result[W];
      for (int c = 0; c < 4; ++c) {
        rgba[p][c].store_aligned(result);
        for (std::size_t l = 0; l < n[p]; ++l) out[c][i + static_cast<std::size_t>(p * W) + l] = result[l];
      }
    }
  }
};

}  // namespace
}  // namespace facet::texture::simd
