// Internal: the display pass's 8-bit store (frame/display.cpp) on xsimd batches, a template on the
// architecture: a row of the exposed float frame, background pixels kept, the others scaled,
// tone-mapped, clamped and encoded (linear or sRGB) into RGBA8 or BGRA8. The same IEEE operations
// in the same order as the scalar tone_map and store (the kernel files are built without FMA
// contraction), so the bytes are the scalar loop's on every ISA. Included only by the per-ISA
// raster files; templates only.
#pragma once

#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "facet/display.hpp"
#include "tile/kernels.hpp"
#include "tile/resolve_simd.hpp"

namespace facet::tile::simd {
namespace {

template <class Arch>
struct DisplayStore {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using BF = typename F::batch_bool_type;
  static constexpr int W = static_cast<int>(F::size);

  // v > 0 ? (v < 1 ? v : 1) : 0, NaN to 0: display.cpp's clamp01.
  static F clamp01(const F& v) { return xsimd::select(v > F(0.0f), xsimd::select(v < F(1.0f), v, F(1.0f)), F(0.0f)); }
  // std::min and std::max of display.cpp's operators: b < a ? b : a, a < b ? b : a.
  static F min2(const F& a, const F& b) { return xsimd::select(b < a, b, a); }
  static F max2(const F& a, const F& b) { return xsimd::select(a < b, b, a); }

  // Khronos PBR Neutral as display.cpp's neutral() computes it.
  static void neutral(F& r, F& g, F& b) {
    constexpr float start = 0.8f - 0.04f, desaturation = 0.15f;
    constexpr float d = 1.0f - start;
    const F x = min2(r, min2(g, b));
    const F offset = xsimd::select(x < F(0.08f), x - F(6.25f) * x * x, F(0.04f));
    r = r - offset, g = g - offset, b = b - offset;
    const F peak = max2(r, max2(g, b));
    const BF compress = !(peak < F(start));
    if (!xsimd::any(compress)) return;
    const F new_peak = F(1.0f) - F(d) * F(d) / (peak + F(d) - F(start));
    const F ratio = new_peak / peak;
    const F k = F(1.0f) - F(1.0f) / (F(desaturation) * (peak - new_peak) + F(1.0f));
    auto squeeze = [&](const F& v) {
      const F s = v * ratio;
      return s + (new_peak - s) * k;
    };
    r = xsimd::select(compress, squeeze(r), r);
    g = xsimd::select(compress, squeeze(g), g);
    b = xsimd::select(compress, squeeze(b), b);
  }
  // Narkowicz's fit as display.cpp's aces().
  static F aces(const F& x) {
    return x * (F(2.51f) * x + F(0.03f)) / (x * (F(2.43f) * x + F(0.59f)) + F(0.14f));
  }

  // Stores pixels [0, n) of the row, n the largest multiple of the batch width; returns n (the
  // caller stores the rest).
  static int row(const DisplayRow& row) {
    const int n = row.width / W * W;
    const int red_shift = row.red == 2 ? 16 : 0, blue_shift = 16 - red_shift;
    auto colour = [&](const F& v) { return row.srgb ? Resolve<Arch>::srgb8(*row.srgb, v) : Resolve<Arch>::unorm8(v); };
    alignas(64) float planes[4][W];
    for (int x = 0; x < n; x += W) {
      const float* p = row.rgba + 4 * static_cast<std::size_t>(x);
      for (int i = 0; i < W; ++i) {
        planes[0][i] = p[4 * i], planes[1][i] = p[4 * i + 1], planes[2][i] = p[4 * i + 2], planes[3][i] = p[4 * i + 3];
      }
      const F r = F::load_aligned(planes[0]), g = F::load_aligned(planes[1]), b = F::load_aligned(planes[2]),
              a = F::load_aligned(planes[3]);
      const BF background = (F::load_unaligned(row.depth + x) == F(row.far)) & (r == F(row.clear[0])) &
                            (g == F(row.clear[1])) & (b == F(row.clear[2])) & (a == F(row.clear[3]));
      const F scale(row.scale);
      F tr = r * scale, tg = g * scale, tb = b * scale;
      tr = xsimd::select(tr > F(0.0f), tr, F(0.0f));  // also NaN to 0
      tg = xsimd::select(tg > F(0.0f), tg, F(0.0f));
      tb = xsimd::select(tb > F(0.0f), tb, F(0.0f));
      if (row.tone_mapping == ToneMapping::neutral) neutral(tr, tg, tb);
      if (row.tone_mapping == ToneMapping::aces) tr = aces(tr), tg = aces(tg), tb = aces(tb);
      tr = xsimd::select(background, clamp01(r), clamp01(tr));
      tg = xsimd::select(background, clamp01(g), clamp01(tg));
      tb = xsimd::select(background, clamp01(b), clamp01(tb));
      const I word = (colour(tr) << red_shift) | (colour(tg) << 8) | (colour(tb) << blue_shift) | (Resolve<Arch>::unorm8(clamp01(a)) << 24);
      word.store_unaligned(reinterpret_cast<std::int32_t*>(row.dst + 4 * static_cast<std::size_t>(x)));  // rows need not be aligned
    }
    return n;
  }
};

}  // namespace
}  // namespace facet::tile::simd
