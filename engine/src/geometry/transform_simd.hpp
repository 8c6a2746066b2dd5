// Internal: geometry::transform_vertices W vertices at a time, a template on the xsimd
// architecture. Only the per-ISA files tile/kernels_{sse2,avx2,avx512}.cpp include this header,
// each compiled with -ffp-contract=off, so every operation is the scalar function's IEEE
// operation in the same order and every output field is bit-identical to it (coverage depends on
// the snapped positions: tests/raster_simd_test.cpp compares them on every ISA). Everything here
// is a template on Arch in an unnamed namespace (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <immintrin.h>

#include <xsimd/xsimd.hpp>

#include "geometry/project.hpp"

namespace facet::geometry::simd {
namespace {

template <class Arch>
struct Transform {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using BF = xsimd::batch_bool<float, Arch>;
  static constexpr std::size_t W = F::size;

  // Rounded to the nearest integer by MXCSR (cvtps2dq), as cvtss2si in the scalar code.
  static I round_to_int(const F& v) {
    if constexpr (W == 16) return I(_mm512_cvtps_epi32(v));
    else if constexpr (W == 8) return I(_mm256_cvtps_epi32(v));
    else return I(_mm_cvtps_epi32(v));
  }
  static I bit(const BF& b, std::int32_t value) { return xsimd::select(xsimd::bool_cast(b), I(value), I(0)); }

  static void run(const Mat4Rows& mvp, const float* positions, std::size_t begin, std::size_t end,
                  const ClipPlanes& planes, const Viewport& viewport, std::array<float, 4>* clip, ScreenVertex* screen) {
    const float* m = mvp.m;
    const float half_w = 0.5f * static_cast<float>(viewport.width), half_h = 0.5f * static_cast<float>(viewport.height);
    const float g = kGuardBandPixels;
    std::size_t i = begin;
    for (; i + W <= end; i += W) {
      alignas(64) float px[W], py[W], pz[W];
      for (std::size_t k = 0; k < W; ++k) {
        const float* p = positions + 3 * (i + k);
        px[k] = p[0], py[k] = p[1], pz[k] = p[2];
      }
      const F x = F::load_aligned(px), y = F::load_aligned(py), z = F::load_aligned(pz);
      F c[4];
      for (int row = 0; row < 4; ++row) {  // m0 x + m1 y + m2 z + m3, left to right, as the scalar code
        const float* r = m + 4 * row;
        c[row] = F(r[0]) * x + F(r[1]) * y + F(r[2]) * z + F(r[3]);
      }
      const F cx = c[0], cy = c[1], cz = c[2], cw = c[3];
      // finite: x - x == 0 exactly when x is finite (inf - inf and NaN give NaN).
      const BF is_finite = ((cx - cx) == F(0.0f)) & ((cy - cy) == F(0.0f)) & ((cz - cz) == F(0.0f)) & ((cw - cw) == F(0.0f));
      const I frustum = bit(cw + cz < F(0.0f), 1) | bit(cw - cz < F(0.0f), 2) | bit(cw + cx < F(0.0f), 4) |
                        bit(cw - cx < F(0.0f), 8) | bit(cw + cy < F(0.0f), 16) | bit(cw - cy < F(0.0f), 32);
      const F gx(planes.guard_x), gy(planes.guard_y);
      const I guard = bit(cw + cz < F(0.0f), 1) | bit(cw - cz < F(0.0f), 2) | bit(gx * cw + cx < F(0.0f), 4) |
                      bit(gx * cw - cx < F(0.0f), 8) | bit(gy * cw + cy < F(0.0f), 16) | bit(gy * cw - cy < F(0.0f), 32);
      // project_xyzw, on every lane (lanes it does not apply to are not stored as projected).
      const F inv_w = F(1.0f) / cw;
      F sx = (cx * inv_w + F(1.0f)) * F(half_w);
      F sy = (F(1.0f) - cy * inv_w) * F(half_h);
      const F sz = F(0.5f) * cz * inv_w + F(0.5f);
      const BF projectable = ((sx - sx) == F(0.0f)) & ((sy - sy) == F(0.0f)) & ((sz - sz) == F(0.0f)) &
                             ((inv_w - inv_w) == F(0.0f));
      // std::clamp(v, -g, g) on finite v: v < -g ? -g : (g < v ? g : v).
      sx = xsimd::select(sx < F(-g), F(-g), xsimd::select(F(g) < sx, F(g), sx));
      sy = xsimd::select(sy < F(-g), F(-g), xsimd::select(F(g) < sy, F(g), sy));
      const F one_sub(static_cast<float>(kSubpixelOne));
      const I ix = round_to_int(sx * one_sub), iy = round_to_int(sy * one_sub);  // |value| <= 2^23
      // Reversed depth (project.hpp): -near / w, on a finite 1/w (sz checks it above).
      const F rz = viewport.depth.reversed ? F(-viewport.depth.near) * inv_w : sz;
      const F lo(viewport.depth.lo()), hi(viewport.depth.far());
      const F depth = xsimd::select(rz < lo, lo, xsimd::select(hi < rz, hi, rz));
      alignas(64) float out_c[4][W], out_z[W], out_inv_w[W];
      alignas(64) std::int32_t out_x[W], out_y[W], out_frustum[W], out_guard[W], out_finite[W], out_projectable[W];
      for (int row = 0; row < 4; ++row) c[row].store_aligned(out_c[row]);
      depth.store_aligned(out_z);
      inv_w.store_aligned(out_inv_w);
      ix.store_aligned(out_x);
      iy.store_aligned(out_y);
      frustum.store_aligned(out_frustum);
      guard.store_aligned(out_guard);
      bit(is_finite, 1).store_aligned(out_finite);
      bit(projectable, 1).store_aligned(out_projectable);
      for (std::size_t k = 0; k < W; ++k) {
        clip[i + k] = {out_c[0][k], out_c[1][k], out_c[2][k], out_c[3][k]};
        ScreenVertex& sv = screen[i + k];
        sv.finite = out_finite[k] != 0;
        sv.frustum = static_cast<std::uint8_t>(out_frustum[k]);
        sv.guard = static_cast<std::uint8_t>(out_guard[k]);
        sv.projected = sv.finite && sv.guard == 0 && out_projectable[k] != 0;
        if (sv.projected) sv.x = out_x[k], sv.y = out_y[k], sv.z = out_z[k], sv.inv_w = out_inv_w[k];
      }
    }
    if (i < end) {
      transform_vertices(mvp, reinterpret_cast<const Vec3*>(positions), i, end, planes, viewport, clip, screen);
    }
  }
};

}  // namespace
}  // namespace facet::geometry::simd
