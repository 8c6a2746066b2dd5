// Internal: texture sampling. Three samplers with one definition (GL 2.1 §3.8.8):
//  - sample_reference: double precision, exact log2; the oracle;
//  - sample_scalar: float, the scalar rasterizer's; the twin of
//  - the SIMD sampler (sample_simd.hpp, one instantiation per ISA), which does the same IEEE float
//    operations in the same order, so both give the same bits (tests/texture_test.cpp).
//
// The float samplers' arithmetic, per coordinate s of a level n texels wide:
//   wrap:    repeat r = s - floor(s) in [0, 1); mirror r = s - 2 floor(s / 2) in [0, 2);
//            clamp r = min(max(s, 0), 1). Not finite, or outside that range: 0. The reduction is
//            exact, so a coordinate of 1e7 is as exact as its float (whole numbers there: the
//            texture is sampled at its corner, never NaN).
//   nearest: i = floor(r n), then folded into [0, n) by the wrap mode;
//   linear:  x = r n - 1/2, i0 = floor(x), i1 = i0 + 1, a = x - i0; both folded into [0, n)
//            (repeat: modulo n; mirror: modulo 2n, then i >= n reads 2n - 1 - i; clamp: to the edge);
//            c = ((t00 (1 - a) + t10 a) (1 - b) + (t01 (1 - a) + t11 a) b) / 255 per channel, with
//            t the stored byte, or for the colour channels of an sRGB texture 255 x its decoding
//            (the float samplers read it from a table rounded to float, the reference computes it).
//   LOD:     rho^2 = max((ds/dx w)^2 + (dt/dx h)^2, (ds/dy w)^2 + (dt/dy h)^2) from the derivatives
//            of (s, t) in the pixel (w, h: level 0's size), lambda = log2(rho^2) / 2 (GL's
//            isotropic rho = max of the two lengths). log2 in float is the exponent plus a
//            degree-5 polynomial of the mantissa: |error| < 2e-5 (tested), so lambda is within
//            1e-5 of exact. lambda <= 0: magnification, bilinear on level 0; else levels
//            floor(lambda) and floor(lambda) + 1 (the last level alone past it), blended by the
//            fraction. rho^2 zero or NaN: level 0; infinite: the last level.
#pragma once

#include <array>
#include <cstdint>

#include "facet/texture.hpp"

namespace facet::texture {

inline constexpr int kMaxLevels = 15;  // 16384 = 2^14: levels 0..14

// Shared by the scalar and SIMD float samplers (plain constants: no inline code crosses ISA files).
// Degree-5 fit of log2(1 + m) on [0, 1) (weighted least squares; with the float rounding of the
// result |error| < 2e-5, tests/texture_test.cpp), highest power last.
inline constexpr float kLog2Poly[5] = {1.4419656991958618f, -0.7096655964851379f, 0.4176080822944641f,
                                       -0.19628861546516418f, 0.04639481008052826f};
inline constexpr float kFarLod = 1000.0f;  // lambda for an infinite rho: past the last level

// Plain data (the per-ISA kernels read it): one texture as the samplers see it.
struct SamplerLevel {
  const std::uint32_t* texels;
  std::int32_t width, height;
  float fwidth, fheight;
};
struct Sampler {
  std::int32_t filter;  // TextureFilter as int
  std::int32_t wrap;    // TextureWrap as int
  std::int32_t levels;
  float lod_width, lod_height;  // level 0's size, for rho
  SamplerLevel level[kMaxLevels];
  // The same per level as tables, for the SIMD sampler's gathers: every level's texels lie in one
  // array from `texels` (level 0), level k's from texel offset[k] (< 2^31: 16384^2 * 4/3).
  const std::uint32_t* texels;
  std::int32_t width[kMaxLevels], height[kMaxLevels], offset[kMaxLevels];
  float fwidth[kMaxLevels], fheight[kMaxLevels];
  // sRGB textures: the float samplers read the colour channels through this table (kSrgbDecode255,
  // stored byte -> 255 x linear) instead of as stored, before filtering; the reference sampler
  // decodes in double. Null: linear.
  const float* decode;
};
Sampler make_sampler(const Texture& texture) noexcept;

// The nearest sRGB byte to a linear value in [0, 1] (clamped; NaN gives 0), IEC 61966-2-1's
// encoding in double: how sRGB mipmaps and converted cube faces store what they averaged decoded.
std::uint32_t encode_srgb8(double linear) noexcept;

// log2(x) as the float samplers compute it, for x normal and finite (the SIMD twin is in sample_simd.hpp).
float log2_approx(float x) noexcept;
// lambda from the derivatives, as the float samplers compute it.
float lod_scalar(const Sampler& s, float dsdx, float dtdx, float dsdy, float dtdy) noexcept;
double lod_reference(const Sampler& s, double dsdx, double dtdx, double dsdy, double dtdy) noexcept;

// RGBA in [0, 1] at (s, t) with level of detail lambda (ignored unless trilinear).
std::array<float, 4> sample_scalar(const Sampler& s, float u, float v, float lambda) noexcept;
std::array<double, 4> sample_reference(const Sampler& s, double u, double v, double lambda) noexcept;

// The fixed-point sampler of the 16-bit pixel tier (linear textures; an sRGB texture's decoding
// needs more than 8 bits, so the tier leaves sRGB textures to the float samplers): the texels,
// levels, wrapping and LOD of sample_scalar, filtered in integers as llvmpipe's AoS sampler does.
// A level's texel coordinate in 8.8 fixed point, rounded to the nearest 1/256 texel,
// x = floor(rs (256 w) - 127.5) (rs the wrapped coordinate, w the level's width: 8 bits below the
// texel need 22 bits of a float's 24 at 16384 texels), columns i0 = x >> 8 and i0 + 1 with weight
// x & 255 (likewise rows); each lerp of two
// bytes (a (256 - f) + b f + 128) >> 8, rounded to a byte: across the row, then down, then for
// trilinear between the levels with weight floor(256 frac(lambda)). Nearest reads the texel
// sample_scalar reads. Returns the four bytes packed as a texel (R in the low byte). Every step is
// an integer or one of the float operations of the SIMD twin (texture/sample_fixed_simd.hpp), so
// the two agree bit for bit.
std::uint32_t sample_fixed_scalar(const Sampler& s, float u, float v, float lambda) noexcept;
// One fixed-point lerp per byte of two packed texels, weight w in [0, 256].
std::uint32_t lerp_bytes(std::uint32_t a, std::uint32_t b, std::uint32_t w) noexcept;
// The double-precision twin of a cube-map lookup (the pixel stages' cube_face, pixel/stages.hpp):
// the face of direction r's major axis and its (s, t) by GL 2.1 table 3.21 (ties: x before y
// before z; t from the face's bottom row), read from faces[0..5] (+X, -X, +Y, -Y, +Z, -Z) at
// level 0.
std::array<double, 4> sample_cube_reference(const Sampler (&faces)[6], double rx, double ry, double rz) noexcept;

}  // namespace facet::texture
