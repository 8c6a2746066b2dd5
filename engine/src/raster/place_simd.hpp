// Internal: placing triangles (raster/assemble.hpp) W at a time, a template on the xsimd
// architecture: the scalar twin's tests in the same order (non-finite, outside the frustum,
// crossing the guard band, not projected, zero area, culled, covering no pixel centre) and the
// same integers for the placed ones (oriented vertices, pixel bounds, top-left biases), so the
// records are bit-identical to the scalar path's (tests/raster_simd_test.cpp, every ISA). Only
// the per-ISA files tile/kernels_{sse2,avx2,avx512}.cpp include this header; everything is a
// template on Arch in an unnamed namespace (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
//
// Exactness: snapped positions inside the guard band are |x|, |y| <= 2^23 (triangle_setup.hpp),
// so differences of two fit in 32 bits and the bounds and biases are exact in 32-bit lanes. Twice
// the area is a difference of two products of edge deltas: when every delta is in [-2^15, 2^15)
// (128 pixels) the difference is exact in 32-bit lanes (bound at its computation); wider triangles are
// handed back to the scalar code (PlaceGroup::scalar), which computes it in 64 bits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <immintrin.h>

#include <xsimd/xsimd.hpp>

#include "geometry/project.hpp"
#include "raster/place.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::raster::simd {
namespace {

template <class Arch>
struct Place {
  using I = xsimd::batch<std::int32_t, Arch>;
  using BI = xsimd::batch_bool<std::int32_t, Arch>;
  static constexpr int W = static_cast<int>(I::size);
  static_assert(kPlaceGroup % W == 0);
  static_assert(sizeof(geometry::ScreenVertex) == 20 && offsetof(geometry::ScreenVertex, frustum) == 16,
                "read as five 32-bit words: x, y, z, 1/w, then the four flag bytes");
  static_assert(offsetof(geometry::ScreenVertex, guard) == 17 && offsetof(geometry::ScreenVertex, finite) == 18 &&
                offsetof(geometry::ScreenVertex, projected) == 19 && sizeof(bool) == 1);

  // The low 32 bits of a * b (exact when the product fits, as here).
  static I mul(const I& a, const I& b) {
    if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
      return I(_mm512_mullo_epi32(a, b));
    } else if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
      return I(_mm256_mullo_epi32(a, b));
    } else {  // sse2: even and odd lanes by the unsigned 32x32->64 multiply (same low bits)
      const __m128i even = _mm_mul_epu32(a, b);
      const __m128i odd = _mm_mul_epu32(_mm_srli_si128(a, 4), _mm_srli_si128(b, 4));
      return I(_mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                                  _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0))));
    }
  }
  // Arithmetic shift right (floor division by 2^N). avx512: the zero-masked form, since GCC 12
  // warns on the plain intrinsic's undefined pass-through operand.
  template <int N>
  static I sra(const I& a) {
    if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
      return I(_mm512_maskz_srai_epi32(__mmask16(0xffff), a, N));
    } else {
      return a >> N;
    }
  }
  static I min(const I& a, const I& b) { return xsimd::select(a < b, a, b); }
  static I max(const I& a, const I& b) { return xsimd::select(a < b, b, a); }
  static I set_if(const BI& c, std::int32_t v, const I& otherwise) { return xsimd::select(c, I(v), otherwise); }
  // Bit l set where lane l is true.
  static std::uint32_t bits(const BI& b) {
    if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
      return static_cast<__mmask16>(b);
    } else if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
      return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(b)));
    } else {
      return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(b)));
    }
  }

  // The W vertices `index` names: x, y, z, 1/w (as their bits) and the flag word, one 128-bit load
  // per vertex and a 4x4 transpose per four lanes, which costs less than five hardware gathers per
  // corner (measured on Zen 4; the figures are in the commit that made it).
  static void load_vertices(const std::int32_t* words, const std::int32_t* index, I& x, I& y, I& z, I& w, I& flags) {
    alignas(64) std::int32_t f[W];
    __m128i q[W / 4][4];
    for (int g = 0; g < W / 4; ++g) {
      __m128 r[4];
      for (int l = 0; l < 4; ++l) {
        const std::int32_t* v = words + 5 * index[4 * g + l];
        r[l] = _mm_loadu_ps(reinterpret_cast<const float*>(v));
        f[4 * g + l] = v[4];
      }
      _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
      for (int c = 0; c < 4; ++c) q[g][c] = _mm_castps_si128(r[c]);
    }
    I* out[4] = {&x, &y, &z, &w};
    for (int c = 0; c < 4; ++c) {
      if constexpr (W == 16) {
        __m512i v = _mm512_castsi128_si512(q[0][c]);
        v = _mm512_inserti32x4(v, q[1][c], 1);
        v = _mm512_inserti32x4(v, q[2][c], 2);
        *out[c] = I(_mm512_inserti32x4(v, q[3][c], 3));
      } else if constexpr (W == 8) {
        *out[c] = I(_mm256_inserti128_si256(_mm256_castsi128_si256(q[0][c]), q[1][c], 1));
      } else {
        *out[c] = I(q[0][c]);
      }
    }
    flags = I::load_aligned(f);
  }

  static void run(const std::uint32_t* triangles, const geometry::ScreenVertex* screen, const PlaceParams& p,
                  PlaceGroup& out) {
    const auto* words = reinterpret_cast<const std::int32_t*>(screen);
    const auto* corners = reinterpret_cast<const std::int32_t*>(triangles);
    out.keep = 0;
    for (int f = 0; f < PlaceGroup::kFates; ++f) out.count[f] = 0;
    for (int g = 0; g < kPlaceGroup; g += W) {
      I x[3], y[3], z[3], w[3], flags[3];
      for (int k = 0; k < 3; ++k) {
        alignas(64) std::int32_t index[W];
        for (int l = 0; l < W; ++l) index[l] = corners[3 * (g + l) + k];
        load_vertices(words, index, x[k], y[k], z[k], w[k], flags[k]);
      }
      // Flag bytes: frustum, guard, finite (0/1), projected (0/1).
      const I all_flags = flags[0] & flags[1] & flags[2], any_flags = flags[0] | flags[1] | flags[2];
      const BI finite = (all_flags & I(0xff0000)) != I(0);
      const BI outside = (all_flags & I(0xff)) != I(0);
      const BI crosses = (any_flags & I(0xff00)) != I(0);
      const BI projected = (all_flags & I(0xff000000)) != I(0);

      const I dx1 = x[1] - x[0], dy1 = y[1] - y[0], dx2 = x[2] - x[0], dy2 = y[2] - y[0];
      // Every delta in [-2^15, 2^15): each product in [-2^30 + 2^15, 2^30], their difference
      // strictly inside (-2^31, 2^31).
      const I half(1 << 15);
      const BI narrow = sra<16>((dx1 + half) | (dy1 + half) | (dx2 + half) | (dy2 + half)) == I(0);
      const I area2 = mul(dx1, dy2) - mul(dx2, dy1);  // as signed_area2, exact on narrow lanes
      const BI positive = area2 > I(0), swapped = area2 < I(0);
      const BI back = p.mirrored ? ~positive : positive;  // is_back_facing
      BI culled(false);
      if (p.cull_back) culled = culled | back;
      if (p.cull_front) culled = culled | ~back;

      // finish_setup: pixels with a sample in the bounds, clipped to the viewport.
      const I lo_x = min(min(x[0], x[1]), x[2]), hi_x = max(max(x[0], x[1]), x[2]);
      const I lo_y = min(min(y[0], y[1]), y[2]), hi_y = max(max(y[0], y[1]), y[2]);
      const I min_px = max(I(0), sra<kSubpixelBits>(lo_x + I(kSubpixelOne - 1 - p.sample_hi)));
      const I max_px = min(I(p.width - 1), sra<kSubpixelBits>(hi_x - I(p.sample_lo)));
      const I min_py = max(I(0), sra<kSubpixelBits>(lo_y + I(kSubpixelOne - 1 - p.sample_hi)));
      const I max_py = min(I(p.height - 1), sra<kSubpixelBits>(hi_y - I(p.sample_lo)));
      const BI empty = (min_px > max_px) | (min_py > max_py);

      // The fate, the scalar code's first failing test; the later tests first, overwritten.
      I fate = set_if(swapped, PlaceGroup::placed_swapped, I(PlaceGroup::placed));
      fate = set_if(empty, PlaceGroup::small, fate);
      fate = set_if(culled, PlaceGroup::culled, fate);
      fate = set_if(area2 == I(0), PlaceGroup::degenerate, fate);
      fate = set_if(~narrow, PlaceGroup::scalar, fate);
      fate = set_if(~projected, PlaceGroup::nonfinite, fate);
      fate = set_if(crosses, PlaceGroup::clip, fate);
      fate = set_if(outside, PlaceGroup::outside, fate);
      fate = set_if(~finite, PlaceGroup::nonfinite, fate);
      fate.store_aligned(out.fate + g);
      // The lanes the caller takes (placed, clipped or handed back), and how many of each fate:
      // a group where none is taken (a mesh's back half, culled) needs no record fields.
      const BI taken = (fate >= I(PlaceGroup::placed)) | (fate == I(PlaceGroup::clip));
      const std::uint32_t taken_bits = bits(taken);
      out.keep |= taken_bits << g;
      for (int f = 0; f < PlaceGroup::kFates; ++f) out.count[f] += __builtin_popcount(bits(fate == I(f)));
      if (!taken_bits) continue;

      // Orient clockwise: exchange vertices 1 and 2 where the area is negative.
      const I ox[3] = {x[0], xsimd::select(swapped, x[2], x[1]), xsimd::select(swapped, x[1], x[2])};
      const I oy[3] = {y[0], xsimd::select(swapped, y[2], y[1]), xsimd::select(swapped, y[1], y[2])};
      const I oz[3] = {z[0], xsimd::select(swapped, z[2], z[1]), xsimd::select(swapped, z[1], z[2])};
      const I ow[3] = {w[0], xsimd::select(swapped, w[2], w[1]), xsimd::select(swapped, w[1], w[2])};
      for (int k = 0; k < 3; ++k) {
        ox[k].store_aligned(out.x[k] + g);
        oy[k].store_aligned(out.y[k] + g);
        oz[k].store_aligned(reinterpret_cast<std::int32_t*>(out.z[k] + g));
        ow[k].store_aligned(reinterpret_cast<std::int32_t*>(out.inv_w[k] + g));
        // is_top_left of edge k, from vertex k+1 to vertex k+2.
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const I ex = ox[b] - ox[a], ey = oy[b] - oy[a];
        const BI top_left = (ey < I(0)) | ((ey == I(0)) & (ex > I(0)));
        set_if(top_left, 0, I(-1)).store_aligned(out.bias[k] + g);
      }
      min_px.store_aligned(out.min_px + g);
      max_px.store_aligned(out.max_px + g);
      min_py.store_aligned(out.min_py + g);
      max_py.store_aligned(out.max_py + g);
      set_if(back, 1, I(0)).store_aligned(out.back_facing + g);
    }
  }
};

}  // namespace
}  // namespace facet::raster::simd
