// Internal: the SIMD resolve, a template on the xsimd architecture: a tile's float planes into
// the caller's image (8-bit RGBA or BGRA, linear or sRGB-encoded, or float RGBA) and depth view,
// rows flipped for y-up views. Blocks no triangle touched are written from the clear colour.
// Included only by the per-ISA raster files (-ffp-contract=off); templates only.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "common/gather_simd.hpp"
#include "io/rows.hpp"
#include "tile/kernels.hpp"

namespace facet::tile::simd {
namespace {

template <class Arch>
struct Resolve {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  static constexpr int W = static_cast<int>(F::size);
  static int imin(int a, int b) { return a < b ? a : b; }

  static std::uint32_t unorm8(float v) {
    const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
    return static_cast<std::uint32_t>(c * 255.0f + 0.5f);  // as to_unorm8 (io/image_convert.hpp)
  }
  // A colour channel of 8-bit output: linear, or sRGB-encoded with the table's thresholds (the
  // search of io/srgb.hpp, written here again: no inline function is shared across ISA files).
  static std::uint32_t colour8(const TileView& tv, float v) {
    if (!tv.srgb) return unorm8(v);
    int k = 0;
    for (int step = 128; step >= 1; step >>= 1) {
      if (v >= tv.srgb->threshold[k + step]) k += step;
    }
    return static_cast<std::uint32_t>(k);
  }
  template <class A>
  static xsimd::batch<std::int32_t, A> unorm8(const xsimd::batch<float, A>& v) {
    using B = xsimd::batch<float, A>;
    const B c = xsimd::select(v > B(0.0f), xsimd::min(v, B(1.0f)), B(0.0f));
    return xsimd::batch_cast<std::int32_t>(c * B(255.0f) + B(0.5f));  // truncation, as the cast above
  }
  // colour8's sRGB byte for a batch: the same count of thresholds, from the table's buckets
  // (io/srgb.hpp): base + (v >= the bucket's threshold) in [2^-13, 1), 0 below (and for NaN), 255
  // from 1 on. One gather.
  template <class A>
  [[gnu::always_inline]] static xsimd::batch<std::int32_t, A> srgb8(const SrgbTable& t, const xsimd::batch<float, A>& v) {
    using B = xsimd::batch<float, A>;
    using Int = xsimd::batch<std::int32_t, A>;
    const auto in = (v >= B(0x1p-13f)) & (v < B(1.0f));  // false for NaN
    const Int bits = xsimd::bitwise_cast<Int>(v);
    const Int b = xsimd::select(xsimd::bool_cast(in), (bits >> SrgbTable::kBucketShift) - Int(SrgbTable::kBucketBias), Int(0));
    const Int e = simd_util::gather32(t.bucket, b);
    const Int k = (e >> SrgbTable::kBaseShift) + xsimd::select((bits & Int(0xffff)) >= (e & Int(SrgbTable::kLowMask)), Int(1), Int(0));
    return xsimd::select(xsimd::bool_cast(in), k,
                         xsimd::select(xsimd::bool_cast(v >= B(1.0f)), Int(255), Int(0)));
  }
  template <class A>
  static xsimd::batch<std::int32_t, A> colour8(const TileView& tv, const xsimd::batch<float, A>& v) {
    return tv.srgb ? srgb8(*tv.srgb, v) : unorm8(v);
  }

  // The commonest resolve: 8-bit RGBA or BGRA, linear or sRGB, no depth output, whole blocks across the
  // tile (fast_resolve). The same conversion as resolve() with nothing decided per pixel: one row
  // of the image at a time, a block's row of 8 pixels per step (avx512: two blocks' rows, 16
  // horizontally adjacent pixels, when both blocks were touched), the planes read at a fixed step.
  static bool fast_resolve(int x0, int x1, const ImageView& color, const DepthView* depth) {
    return !depth && color.format != PixelFormat::rgba32f && (x1 - x0) % kBlock == 0;
  }
  static std::uint32_t clear_word(const TileView& tv, int red_shift, int blue_shift) {
    return (colour8(tv, tv.clear[0]) << red_shift) | (colour8(tv, tv.clear[1]) << 8) |
           (colour8(tv, tv.clear[2]) << blue_shift) | (unorm8(tv.clear[3]) << 24);
  }
  static void resolve_fast(const TileView& tv, int x0, int y0, int x1, int y1, const ImageView& color) {
    tv.srgb ? resolve_unorm8<true>(tv, x0, y0, x1, y1, color) : resolve_unorm8<false>(tv, x0, y0, x1, y1, color);
  }
  template <bool Srgb>
  static void resolve_unorm8(const TileView& tv, int x0, int y0, int x1, int y1, const ImageView& color) {
    static_assert(W == 4 || W == 8 || W == 16);
    const int red_shift = color.format == PixelFormat::bgra8 ? 16 : 0, blue_shift = 16 - red_shift;
    const int blocks_per_row = tv.size / kBlock, blocks = (x1 - x0) / kBlock;
    const std::uint32_t clear = clear_word(tv, red_shift, blue_shift);
    constexpr int kLane = W < kBlock ? W : kBlock;  // pixels per store in the one-block steps
    using Half = std::conditional_t<W == 16, xsimd::batch<std::int32_t, xsimd::fma3<xsimd::avx2>>, I>;
    using HalfF = std::conditional_t<W == 16, xsimd::batch<float, xsimd::fma3<xsimd::avx2>>, F>;
    static_assert(Half::size == kLane);
    const auto channel = [&](const auto& v) {
      if constexpr (Srgb) {
        return srgb8(*tv.srgb, v);
      } else {
        return unorm8(v);
      }
    };
    const auto word = [&](const auto& r, const auto& g, const auto& b, const auto& a) {
      return (channel(r) << red_shift) | (channel(g) << 8) | (channel(b) << blue_shift) | (unorm8(a) << 24);
    };
    for (int y = y0; y < y1; ++y) {
      const int ty = y - y0;
      auto* dst = reinterpret_cast<std::int32_t*>(io::row_bytes(color, y) + 4 * static_cast<std::size_t>(x0));
      const std::uint8_t* touched = tv.touched + (ty / kBlock) * blocks_per_row;
      const std::size_t first = static_cast<std::size_t>((ty / kBlock) * blocks_per_row) * kBlockPixels +
                                static_cast<std::size_t>((ty % kBlock) * kBlock);
      const float *r = tv.plane[0] + first, *g = tv.plane[1] + first, *b = tv.plane[2] + first,
                  *a = tv.plane[3] + first;
      for (int bx = 0; bx < blocks;) {
        std::int32_t* out = dst + bx * kBlock;
        const std::size_t at = static_cast<std::size_t>(bx) * kBlockPixels;
        if constexpr (W == 16) {  // the rows of two touched blocks in one batch, the left block low
          if (bx + 1 < blocks && touched[bx] && touched[bx + 1]) {
            const auto pair = [&](const float* p) {
              p += at;
              return F(_mm512_insertf32x8(_mm512_castps256_ps512(_mm256_load_ps(p)), _mm256_load_ps(p + kBlockPixels), 1));
            };
            word(pair(r), pair(g), pair(b), pair(a)).store_unaligned(out);  // image rows need not be aligned
            bx += 2;
            continue;
          }
        }
        if (!touched[bx]) {
          for (int i = 0; i < kBlock; i += kLane) Half(static_cast<std::int32_t>(clear)).store_unaligned(out + i);
        } else {
          for (int i = 0; i < kBlock; i += kLane) {
            word(HalfF::load_aligned(r + at + i), HalfF::load_aligned(g + at + i), HalfF::load_aligned(b + at + i),
                 HalfF::load_aligned(a + at + i))
                .store_unaligned(out + i);
          }
        }
        ++bx;
      }
    }
  }

  // Resolve works on rows of 8 pixels: avx512 uses its avx2 half (see kernels_avx512.cpp).
  static void resolve(const TileView& tv, int x0, int y0, int x1, int y1, const ImageView& color,
                      const DepthView* depth) {
    const int blocks_per_row = tv.size / kBlock;
    const int width = x1 - x0;
    // RGBA8 and BGRA8 as little-endian words: channel c goes to byte shift[c] / 8.
    const int red_shift = color.format == PixelFormat::bgra8 ? 16 : 0, blue_shift = 16 - red_shift;
    const std::uint32_t clear_word = Resolve::clear_word(tv, red_shift, blue_shift);
    const std::uint8_t clear_bytes[4] = {static_cast<std::uint8_t>(clear_word), static_cast<std::uint8_t>(clear_word >> 8),
                                         static_cast<std::uint8_t>(clear_word >> 16),
                                         static_cast<std::uint8_t>(clear_word >> 24)};
    if (fast_resolve(x0, x1, color, depth)) {
      resolve_fast(tv, x0, y0, x1, y1, color);
      return;
    }
    for (int y = y0; y < y1; ++y) {
      const int ty = y - y0;
      std::uint8_t* row = io::row_bytes(color, y);
      // Depth and float colour buffers may have any alignment (image.hpp): bytes and memcpy only.
      std::uint8_t* depth_row = depth ? io::row_bytes(*depth, y) : nullptr;
      for (int bx = 0; bx * kBlock < width; ++bx) {
        const int block = (ty / kBlock) * blocks_per_row + bx;
        const std::size_t src =
            static_cast<std::size_t>(block) * kBlockPixels + static_cast<std::size_t>((ty % kBlock) * kBlock);
        const int x = x0 + bx * kBlock;
        const int n = imin(kBlock, width - bx * kBlock);
        if (!tv.touched[block]) {  // still the clear colour: converted once per tile, as below
          if (depth_row) {
            const float f = tv.depth_reversed ? 0.0f - tv.depth_far : tv.depth_far;  // the output's far value (0, not -0)
            const float far_depth[kBlock] = {f, f, f, f, f, f, f, f};
            std::memcpy(depth_row + 4 * static_cast<std::size_t>(x), far_depth, 4 * static_cast<std::size_t>(n));
          }
          if (color.format == PixelFormat::rgba32f) {
            for (int i = 0; i < n; ++i) std::memcpy(row + 16 * static_cast<std::size_t>(x + i), tv.clear, 16);
          } else {
            auto* dst = reinterpret_cast<std::int32_t*>(row + 4 * static_cast<std::size_t>(x));
            int i = 0;
            if constexpr (W <= kBlock) {
              for (; i + W <= n; i += W) I(static_cast<std::int32_t>(clear_word)).store_unaligned(dst + i);
            }
            for (; i < n; ++i) std::memcpy(dst + i, clear_bytes, 4);
          }
          continue;
        }
        const float* r = tv.plane[0] + src;
        const float* g = tv.plane[1] + src;
        const float* b = tv.plane[2] + src;
        const float* a = tv.plane[3] + src;
        if (depth_row) {
          if (tv.depth_reversed) {  // the output is near / w: the stored value negated
            float out[kBlock];
            for (int i = 0; i < n; ++i) out[i] = 0.0f - tv.plane[4][src + static_cast<std::size_t>(i)];
            std::memcpy(depth_row + 4 * static_cast<std::size_t>(x), out, 4 * static_cast<std::size_t>(n));
          } else {
            std::memcpy(depth_row + 4 * static_cast<std::size_t>(x), tv.plane[4] + src, 4 * static_cast<std::size_t>(n));
          }
        }
        if (color.format == PixelFormat::rgba32f) {
          // Four pixels at a time: the planes' rows transposed into RGBA (SSE, in every ISA file);
          // float images may have any alignment, so unaligned stores.
          float* out = reinterpret_cast<float*>(row + 16 * static_cast<std::size_t>(x));
          int i = 0;
          for (; i + 4 <= n; i += 4) {
            __m128 vr = _mm_loadu_ps(r + i), vg = _mm_loadu_ps(g + i), vb = _mm_loadu_ps(b + i), va = _mm_loadu_ps(a + i);
            _MM_TRANSPOSE4_PS(vr, vg, vb, va);
            _mm_storeu_ps(out + 4 * i, vr);
            _mm_storeu_ps(out + 4 * i + 4, vg);
            _mm_storeu_ps(out + 4 * i + 8, vb);
            _mm_storeu_ps(out + 4 * i + 12, va);
          }
          for (; i < n; ++i) {
            const float rgba[4] = {r[i], g[i], b[i], a[i]};
            std::memcpy(out + 4 * i, rgba, 16);
          }
          continue;
        }
        auto* dst = reinterpret_cast<std::uint32_t*>(row + 4 * static_cast<std::size_t>(x));
        int i = 0;
        if constexpr (W <= kBlock) {
          if (n == kBlock) {
            for (; i < kBlock; i += W) {
              const I word = (colour8(tv, F::load_unaligned(r + i)) << red_shift) |
                             (colour8(tv, F::load_unaligned(g + i)) << 8) |
                             (colour8(tv, F::load_unaligned(b + i)) << blue_shift) | (unorm8(F::load_unaligned(a + i)) << 24);
              // Unaligned store: image rows need not be 4-byte aligned.
              word.store_unaligned(reinterpret_cast<std::int32_t*>(dst + i));
            }
          }
        }
        for (; i < n; ++i) {
          const std::uint32_t u = (colour8(tv, r[i]) << red_shift) | (colour8(tv, g[i]) << 8) | (colour8(tv, b[i]) << blue_shift) |
                                  (unorm8(a[i]) << 24);
          auto* d = reinterpret_cast<std::uint8_t*>(dst + i);
          d[0] = static_cast<std::uint8_t>(u), d[1] = static_cast<std::uint8_t>(u >> 8);
          d[2] = static_cast<std::uint8_t>(u >> 16), d[3] = static_cast<std::uint8_t>(u >> 24);
        }
      }
    }
  }
};

}  // namespace
}  // namespace facet::tile::simd
