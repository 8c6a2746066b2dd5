// Internal: the shadow-map lookup (map_lookup.hpp) on W points at a time, a template on the
// xsimd architecture, instantiated in the per-ISA raster files (compiled with -ffp-contract=off).
// Every step is the scalar twin's (map_visibility_scalar in map.cpp) IEEE operation in the same
// order, lane by lane, so the visibility is the same bits; the filter's taps are gathered.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "common/gather_simd.hpp"
#include "shadow/map_lookup.hpp"

namespace facet::shadow::simd {
namespace {

template <class Arch>
struct MapSimd {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using B = xsimd::batch_bool<float, Arch>;
  static constexpr std::size_t W = F::size;

  // Points [first, first + W) (lanes past `count` are zeros and come out invalid).
  static F batch(const MapLookup& m, const float* const (&in)[6], std::size_t stride, std::size_t first, std::size_t count) {
    alignas(64) float lane[6][W];
    for (std::size_t l = 0; l < W; ++l) {
      const bool real = first + l < count;
      for (int k = 0; k < 6; ++k) lane[k][l] = real ? in[k][(first + l) * stride] : 0.0f;
    }
    const F x = F::load_aligned(lane[0]), y = F::load_aligned(lane[1]), z = F::load_aligned(lane[2]);
    const F a = F::load_aligned(lane[3]), b = F::load_aligned(lane[4]), c = F::load_aligned(lane[5]);
    const F zero(0.0f), one(1.0f);
    const F lx = m.directional ? F(m.light[0]) : F(m.light[0]) - x;
    const F ly = m.directional ? F(m.light[1]) : F(m.light[1]) - y;
    const F lz = m.directional ? F(m.light[2]) : F(m.light[2]) - z;
    const F n2 = (a * a + b * b) + c * c, l2 = (lx * lx + ly * ly) + lz * lz;
    B valid = (n2 > zero) && (l2 > zero) && (n2 < F(1e30f)) && (l2 < F(1e30f)) && ((x - x) == zero) &&
              ((y - y) == zero) && ((z - z) == zero);
    const F inv_n = one / xsimd::sqrt(n2), inv_l = one / xsimd::sqrt(l2);
    F cos_nl = (((a * lx + b * ly) + c * lz) * inv_n) * inv_l;
    cos_nl = xsimd::min(xsimd::max(cos_nl, zero), one);
    const F sin_nl = xsimd::sqrt(xsimd::max(one - cos_nl * cos_nl, zero));
    const F tan_nl = xsimd::min(sin_nl / cos_nl, F(kMaxSlopeTangent));
    // The face: a cube's by the major axis of the way from the light in world space.
    I face(0);
    F row[4][4];
    if (m.kind == MapLookup::cube) {
      const F dx = x - F(m.light[0]), dy = y - F(m.light[1]), dz = z - F(m.light[2]);
      const float* r = m.eye_to_world;
      const F wx = (F(r[0]) * dx + F(r[1]) * dy) + F(r[2]) * dz;
      const F wy = (F(r[3]) * dx + F(r[4]) * dy) + F(r[5]) * dz;
      const F wz = (F(r[6]) * dx + F(r[7]) * dy) + F(r[8]) * dz;
      const F ax = xsimd::abs(wx), ay = xsimd::abs(wy), az = xsimd::abs(wz);
      const B on_x = (ax >= ay) && (ax >= az), on_y = !on_x && (ay >= az);
      const F major = xsimd::select(on_x, wx, xsimd::select(on_y, wy, wz));
      const I axis = xsimd::select(xsimd::bool_cast(on_x), I(0),
                                   xsimd::select(xsimd::bool_cast(on_y), I(1), I(2)));
      face = axis + axis + xsimd::select(xsimd::bool_cast(major < zero), I(1), I(0));
      const I base = face * I(16);
      for (int k = 0; k < 16; ++k) {
        row[k / 4][k % 4] = xsimd::bitwise_cast<F>(
            simd_util::gather32<Arch>(reinterpret_cast<const std::int32_t*>(&m.to_clip[0][0]), base + I(k)));
      }
    } else {
      for (int k = 0; k < 16; ++k) row[k / 4][k % 4] = F(m.to_clip[0][k]);
    }
    F cc[4];
    for (int r = 0; r < 4; ++r) cc[r] = ((row[r][0] * x + row[r][1] * y) + row[r][2] * z) + row[r][3];
    const F texel = m.kind == MapLookup::orthographic ? F(m.reach) * F(m.texel)
                                                      : F(m.reach) * (F(m.texel_per_w) * xsimd::max(cc[3], zero));
    const F along_n = (texel * F(m.bias_normal)) * inv_n;
    const F along_l = (texel * (F(m.bias_constant) + F(m.bias_slope) * tan_nl)) * inv_l;
    const F o0 = along_n * a + along_l * lx, o1 = along_n * b + along_l * ly, o2 = along_n * c + along_l * lz;
    for (int r = 0; r < 4; ++r) cc[r] = cc[r] + ((row[r][0] * o0 + row[r][1] * o1) + row[r][2] * o2);
    valid = valid && (cc[3] > zero);
    const F inv_w = one / cc[3];
    const F half(0.5f * static_cast<float>(m.resolution));
    const F u = (cc[0] * inv_w + one) * half, v = (one - cc[1] * inv_w) * half;
    const F depth = xsimd::min(xsimd::max(F(0.5f) * (cc[2] * inv_w) + F(0.5f), zero), one);
    const F shift(m.taps == 1 ? 0.0f : 0.5f * static_cast<float>(m.taps) - 0.5f);
    const F su = u - shift, sv = v - shift;
    const F fu = xsimd::floor(su), fv = xsimd::floor(sv);
    valid = valid && (fu > F(-1e9f)) && (fu < F(1e9f)) && (fv > F(-1e9f)) && (fv < F(1e9f));
    const I x0 = xsimd::batch_cast<std::int32_t>(xsimd::select(valid, fu, zero));
    const I y0 = xsimd::batch_cast<std::int32_t>(xsimd::select(valid, fv, zero));
    const F fx = su - fu, fy = sv - fv;
    const I n(m.resolution);
    const I face_base = face * (n * n);
    const auto* texels = reinterpret_cast<const std::int32_t*>(m.depth);
    // Lit where the texel is outside the map (nothing casts there) or not nearer than the point.
    auto lit = [&](const I& tx, const I& ty) {
      const auto inside = (tx >= I(0)) && (tx < n) && (ty >= I(0)) && (ty < n);
      const I at = xsimd::select(inside, face_base + ty * n + tx, I(0));
      const F stored = xsimd::bitwise_cast<F>(simd_util::gather32<Arch>(texels, at));
      return !xsimd::bool_cast(inside) || (depth <= stored);
    };
    F result;
    if (m.taps == 1) {
      result = xsimd::select(lit(x0, y0), one, zero);
    } else {
      const int last = m.taps - 1;
      F sum = zero;
      for (int j = 0; j <= last; ++j) {
        F r = zero;
        for (int i = 0; i <= last; ++i) {
          const F w = i == 0 ? one - fx : i == last ? fx : one;
          r = r + xsimd::select(lit(x0 + I(i), y0 + I(j)), w, zero);
        }
        const F wy = j == 0 ? one - fy : j == last ? fy : one;
        sum = sum + wy * r;
      }
      result = sum / F(static_cast<float>(last * last));
    }
    return xsimd::select(valid, result, one);
  }

  static void run(const MapLookup& m, std::size_t count, const float* px, const float* py, const float* pz,
                  const float* nx, const float* ny, const float* nz, std::size_t stride, float* visible) {
    const float* const in[6] = {px, py, pz, nx, ny, nz};
    for (std::size_t first = 0; first < count; first += W) {
      alignas(64) float out[W];
      batch(m, in, stride, first, count).store_aligned(out);
      for (std::size_t l = 0; l < W && first + l < count; ++l) visible[first + l] = out[l];
    }
  }
};

}  // namespace
}  // namespace facet::shadow::simd
