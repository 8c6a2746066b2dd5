// Internal: the arithmetic of the surface program (raster_kernels.hpp, Draw): texture environment,
// colour sum, fog and blending, written once as templates on the value type, so the scalar
// rasterizer (V = float) and the SIMD kernels (V = an xsimd batch) do the same IEEE operations in
// the same order (every file that includes this is built with -ffp-contract=off): the scalar and
// SIMD paths give the same bits for the same interpolated inputs. Everything is in an unnamed
// namespace: no inline function crosses ISA files (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "raster/raster_kernels.hpp"

namespace facet::raster::surface {
namespace {

using simd::Draw;
using simd::Fog;

// Selection and bounds for both value types (NaN compares false: a NaN input becomes the "else").
inline float pick(bool c, float a, float b) { return c ? a : b; }
template <class B, class M>
B pick(const M& c, const B& a, const B& b) {
  return xsimd::select(c, a, b);
}
template <class V>
V saturate(const V& x) {  // [0, 1]; NaN -> 0
  return pick(x > V(0.0f), pick(x < V(1.0f), x, V(1.0f)), V(0.0f));
}
template <class V>
V positive(const V& x) {  // >= 0; NaN -> 0
  return pick(x > V(0.0f), x, V(0.0f));
}
template <class V>
V finish(const V& x, bool clamp) {
  return clamp ? saturate(x) : positive(x);
}

// 2^y for y <= 0, |relative error| < 2e-7: y = n + r with n = floor(y + 1/2), r in [-1/2, 1/2),
// 2^r by its Taylor series to degree 6 (remainder (ln2/2)^7 / 7! < 1.4e-7), 2^n through the
// exponent bits. y < -126 (and NaN) gives 0.
inline constexpr float kExp2Taylor[7] = {1.0f,
                                         0.693147180559945f,
                                         0.240226506959101f,
                                         0.0555041086648216f,
                                         0.00961812910762848f,
                                         0.00133335581464284f,
                                         0.000154035303933816f};
inline float exp2_nonpositive(float y) {
  if (!(y >= -126.0f)) return 0.0f;
  const float n = std::floor(y + 0.5f);
  const float r = y - n;
  float p = kExp2Taylor[6];
  for (int k = 5; k >= 0; --k) p = p * r + kExp2Taylor[k];
  const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, 4);
  return p * scale;
}
template <class B>
B exp2_nonpositive(const B& y) {
  using I = xsimd::batch<std::int32_t, typename B::arch_type>;
  const auto ok = y >= B(-126.0f);
  const B ys = xsimd::select(ok, y, B(0.0f));
  const B n = xsimd::floor(ys + B(0.5f));
  const B r = ys - n;
  B p(kExp2Taylor[6]);
  for (int k = 5; k >= 0; --k) p = p * r + B(kExp2Taylor[k]);
  const I bits = (xsimd::batch_cast<std::int32_t>(n) + I(127)) << 23;
  return xsimd::select(ok, p * xsimd::bitwise_cast<B>(bits), B(0.0f));
}

inline constexpr float kLog2e = 1.44269504088896f;

// The fog factor at eye depth z (Fog in raster_kernels.hpp), in [0, 1].
template <class V>
V fog_factor(const Fog& fog, const V& z) {
  if (fog.mode == FogMode::linear) {
    if (fog.scale == 0.0f) return pick(z < V(fog.end), V(1.0f), V(0.0f));
    return saturate((V(fog.end) - z) * V(fog.scale));
  }
  const V t = V(fog.density) * z;
  const V e = fog.mode == FogMode::exp ? t : t * t;
  return saturate(exp2_nonpositive(V(0.0f) - e * V(kLog2e)));
}

// One fragment's colour (c[0..2]) and alpha (c[3]) through the texture environment (GL 2.1
// table 3.22, RGBA texture): primary colour p, fragment alpha a, texel t (RGBA), then the emission
// e (Draw::emission; null: none) added as a second texture unit under GL_ADD would add it, then
// the colour sum with the secondary colour s, then fog with factor f (f null: no fog).
template <class V>
void shade_fragment(const Draw& d, const Fog& fog, const V (&p)[3], const V& a, const V* t, const V* e, const V* s,
                    const V* f, V (&c)[4]) {
  if (!t) {
    for (int k = 0; k < 3; ++k) c[k] = p[k];
    c[3] = a;
  } else {
    switch (d.texture_env) {
      case TextureMode::replace:
        for (int k = 0; k < 3; ++k) c[k] = t[k];
        c[3] = t[3];
        break;
      case TextureMode::decal:
        for (int k = 0; k < 3; ++k) c[k] = p[k] * (V(1.0f) - t[3]) + t[k] * t[3];
        c[3] = a;
        break;
      case TextureMode::add:
        for (int k = 0; k < 3; ++k) c[k] = finish(p[k] + t[k], d.clamp);
        c[3] = a * t[3];
        break;
      default:  // modulate
        for (int k = 0; k < 3; ++k) c[k] = p[k] * t[k];
        c[3] = a * t[3];
        break;
    }
  }
  if (e) {
    for (int k = 0; k < 3; ++k) c[k] = finish(c[k] + e[k], d.clamp);
  }
  if (s) {
    for (int k = 0; k < 3; ++k) c[k] = finish(c[k] + s[k], d.clamp);
  }
  if (f && fog.mode != FogMode::none) {
    for (int k = 0; k < 3; ++k) c[k] = *f * c[k] + (V(1.0f) - *f) * V(fog.color[k]);
  }
}

// The alpha a fragment will have (what the alpha test sees) without computing its colour.
template <class V>
V fragment_alpha(const Draw& d, const V& a, const V* t) {
  if (!t) return a;
  if (d.texture_env == TextureMode::replace) return t[3];
  if (d.texture_env == TextureMode::decal) return a;
  return a * t[3];
}

// Blends source c (RGBA) over destination dst (RGBA) with GL's factors (the same for alpha as for
// colour): alpha (SRC_ALPHA, ONE_MINUS_SRC_ALPHA), premultiplied (ONE, ONE_MINUS_SRC_ALPHA), add
// (ONE, ONE), multiply (DST_COLOR, ZERO), subtract (reverse subtract: dst - src); saturated.
template <class V>
void blend(const Draw& d, const V (&c)[4], V (&dst)[4]) {
  const V a = c[3];
  for (int k = 0; k < 4; ++k) {
    V out;
    switch (d.blend) {
      case BlendMode::alpha: out = c[k] * a + dst[k] * (V(1.0f) - a); break;
      case BlendMode::premultiplied: out = c[k] + dst[k] * (V(1.0f) - a); break;
      case BlendMode::add: out = c[k] + dst[k]; break;
      case BlendMode::multiply: out = c[k] * dst[k]; break;
      case BlendMode::subtract: out = dst[k] - c[k]; break;
      default: out = c[k]; break;
    }
    dst[k] = finish(out, d.clamp);
  }
}

}  // namespace
}  // namespace facet::raster::surface
