// Internal: the pixel stages, each written once as a template on the value type: V = float (the
// scalar rasterizer, one pixel) or an xsimd batch (the SIMD programs, programs_simd.hpp, one
// batch of pixels). Both do the same IEEE operations in the same order (every file that includes
// this is built with -ffp-contract=off), so the scalar and SIMD paths give the same bits for the
// same interpolated inputs. A draw's pixel program (program.hpp, Draw) runs, in GL 2.1's
// order (§3.8.13, §3.10, §4.1):
//   texture coordinates (uv_from_planes) -> sample -> alpha test (fragment_alpha) -> depth write
//   -> fog factor -> emission (and baked light) -> primary and secondary colour (vertex_colours; Phong: light) ->
//   texture environment -> add emission -> colour sum -> fog -> blend -> store.
// The stages are always inlined: a program is the sequence of its stages' code, with no call
// between them (out of line, GCC left calls to the colour, blend and fragment stages in the
// blended program). Everything is in an unnamed namespace: no inline function crosses ISA files (an inline function
// compiled into files with different ISA flags is merged by the linker, and the wider copy may run
// on a CPU without it).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "pixel/program.hpp"
#include "raster/triangle_setup.hpp"
#include "raster/varyings.hpp"

namespace facet::pixel {
namespace {

using pixel::Draw;
using pixel::Fog;

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
// The clamp of a colour sum and of blending: to [0, 1], or (HDR float output) only below at 0.
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

// The fog factor at eye depth z (Fog in program.hpp), in [0, 1].
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

// Texture coordinates at a pixel, scaled by the draw's uv_scale, and their screen derivatives
// (for the LOD): u = U / W' with U = u/w and W' = 1/w affine on screen, so
// du/dx = (dU/dx - u dW'/dx) / W'. `big_u`, `big_v`: U and V interpolated; cw: 1 / W' (clip w);
// u_dx .. w_dy: the U, V and W' planes' steps.
template <class V>
struct Uv {
  V u, v, dudx, dvdx, dudy, dvdy;
};
template <class V, class D>
[[gnu::always_inline]] inline Uv<V> uv_from_planes(const Draw& d, const V& big_u, const V& big_v, const V& cw, const D& u_dx, const D& u_dy,
                     const D& v_dx, const D& v_dy, const D& w_dx, const D& w_dy) {
  const V u = big_u * cw, v = big_v * cw;
  const V dudx = (u_dx - u * w_dx) * cw, dudy = (u_dy - u * w_dy) * cw;
  const V dvdx = (v_dx - v * w_dx) * cw, dvdy = (v_dy - v * w_dy) * cw;
  const V su(d.uv_scale[0]), sv(d.uv_scale[1]);
  return {su * u, sv * v, su * dudx, sv * dvdx, su * dudy, sv * dvdy};
}

// The emission the draw adds after its texture environment (Draw::emission): the material's,
// times the RGB of its emission texture when it has one; sample(sampler, rgba) samples it.
template <class V, class Sample>
[[gnu::always_inline]] inline void emission(const Draw& d, const Sample& sample, V (&e)[3]) {
  if (d.emission_texture) {
    V t[4];
    sample(*d.emission_texture, t);
    for (int k = 0; k < 3; ++k) e[k] = V(d.emission_rgb[k]) * t[k];
  } else {
    for (int k = 0; k < 3; ++k) e[k] = V(d.emission_rgb[k]);
  }
}

// Baked light (Draw::lightmap), added to the emission e: the lightmap's RGB (sample(sampler, rgba)
// reads it at the pixel's lightmap coordinates, level 0) times Draw::lightmap_albedo, times the
// texel's RGB on a textured draw: the albedo times the baked light, modulated by the texture as the
// lit colour would be (GL_MODULATE is the one texture environment lightmaps take).
template <class V, class Sample>
[[gnu::always_inline]] inline void lightmap_light(const Draw& d, const Sample& sample, const V* texel, V (&e)[3]) {
  if (!d.lightmap) return;
  V t[4];
  sample(*d.lightmap, t);
  for (int k = 0; k < 3; ++k) {
    V x = V(d.lightmap_albedo[k]) * t[k];
    if (texel) x = x * texel[k];
    e[k] = e[k] + x;
  }
}

// Flat and Gouraud lighting's colours at a pixel: the primary colour p and, where the lighting
// kept the specular apart (a textured draw), the secondary colour s; returns s, or null when the
// specular is in p. Flat: the triangle's colours; Gouraud: value(a) interpolates attribute a.
template <class V, class Value>
[[gnu::always_inline]] inline const V* vertex_colours(ShadingMode shading, const Draw& d, const raster::ScreenTriangle& t,
                                                    const Value& value, V (&p)[3], V (&s)[3]) {
  if (shading == ShadingMode::flat) {
    for (int c = 0; c < 3; ++c) p[c] = V(t.flat_rgb[c]), s[c] = V(t.flat_secondary[c]);
    return d.separate_specular ? s : nullptr;
  }
  const int colour = d.layout.at(raster::Varying::front_color), second = d.layout.at(raster::Varying::front_secondary);
  for (int c = 0; c < 3; ++c) p[c] = value(colour + c);
  if (second < 0) return nullptr;
  for (int c = 0; c < 3; ++c) s[c] = value(second + c);
  return s;
}

// The texture environment (GL 2.1 table 3.22, RGBA texture) on primary colour p and fragment
// alpha a with texel t, into c (RGB, alpha): texture_environment_as with the mode fixed at
// compile time (a fused program's), texture_environment with the draw's (t null: no texture).
// GL_MODULATE on one channel (colour or alpha): fragment times texel.
template <class V>
[[gnu::always_inline]] inline V modulate(const V& fragment, const V& texel) {
  return fragment * texel;
}
template <TextureMode M, class V>
[[gnu::always_inline]] inline void texture_environment_as(const Draw& d, const V (&p)[3], const V& a, const V* t, V (&c)[4]) {
  if constexpr (M == TextureMode::replace) {
    for (int k = 0; k < 3; ++k) c[k] = t[k];
    c[3] = t[3];
  } else if constexpr (M == TextureMode::decal) {
    for (int k = 0; k < 3; ++k) c[k] = p[k] * (V(1.0f) - t[3]) + t[k] * t[3];
    c[3] = a;
  } else if constexpr (M == TextureMode::add) {
    for (int k = 0; k < 3; ++k) c[k] = finish(p[k] + t[k], d.clamp);
    c[3] = a * t[3];
  } else {
    for (int k = 0; k < 3; ++k) c[k] = modulate(p[k], t[k]);
    c[3] = modulate(a, t[3]);
  }
}
template <class V>
[[gnu::always_inline]] inline void texture_environment(const Draw& d, const V (&p)[3], const V& a, const V* t, V (&c)[4]) {
  if (!t) {
    for (int k = 0; k < 3; ++k) c[k] = p[k];
    c[3] = a;
    return;
  }
  switch (d.texture_env) {
    case TextureMode::replace: texture_environment_as<TextureMode::replace>(d, p, a, t, c); break;
    case TextureMode::decal: texture_environment_as<TextureMode::decal>(d, p, a, t, c); break;
    case TextureMode::add: texture_environment_as<TextureMode::add>(d, p, a, t, c); break;
    default: texture_environment_as<TextureMode::modulate>(d, p, a, t, c); break;
  }
}
// Adds x[0..2] (the emission after texturing, as a second texture unit under GL_ADD would, or the
// secondary colour: the colour sum) to c's RGB.
template <class V>
[[gnu::always_inline]] inline void add_colour(const Draw& d, const V* x, V (&c)[4]) {
  for (int k = 0; k < 3; ++k) c[k] = finish(c[k] + x[k], d.clamp);
}
// Fog with factor f: c = f c + (1 - f) fog colour; alpha unchanged.
template <class V>
[[gnu::always_inline]] inline void apply_fog(const Fog& fog, const V& f, V (&c)[4]) {
  for (int k = 0; k < 3; ++k) c[k] = f * c[k] + (V(1.0f) - f) * V(fog.color[k]);
}

// --- Environment mapping (Material::environment) --------------------------------------------

// Whether any lane of a mask is set (bool: the one lane).
inline bool any_lane(bool m) { return m; }
template <class M>
bool any_lane(const M& m) {
  return xsimd::any(m);
}
// Lane-wise and, not for both mask types.
inline bool lane_and(bool a, bool b) { return a && b; }
template <class M>
M lane_and(const M& a, const M& b) {
  return a & b;
}
inline bool lane_not(bool a) { return !a; }
template <class M>
M lane_not(const M& a) {
  return ~a;
}
// sqrt for both value types (IEEE: correctly rounded on every path).
inline float root(float x) { return std::sqrt(x); }
template <class V>
V root(const V& x) {
  return xsimd::sqrt(x);
}

// The texture coordinates the environment is looked up with, from eye-space position p and
// normal n (neither need be unit): GL's texgen (Material::environment). sphere and normal: (s, t,
// 0); cube: the reflection r turned into world space by `to_world` (3x3, row-major: the view's
// rotation transposed; GL's texture matrix), any length (only its direction picks the texel). A point at the
// eye looks down -z; a zero normal reflects nothing (r = u). The sphere map's singular direction,
// r = (0, 0, -1) (m = 0: grazing the silhouette straight ahead), reads its rim at (1, 1/2).
template <class V>
[[gnu::always_inline]] inline void environment_coords(EnvironmentMode mode, const float* to_world, const V (&p)[3],
                                                      const V (&n)[3], V (&c)[3]) {
  const V nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  const V n_len = root(nn);
  const V n_inv = pick(n_len > V(0.0f), V(1.0f) / n_len, V(0.0f));
  const V nu[3] = {n[0] * n_inv, n[1] * n_inv, n[2] * n_inv};
  if (mode == EnvironmentMode::normal) {
    c[0] = nu[0] * V(0.5f) + V(0.5f);
    c[1] = nu[1] * V(0.5f) + V(0.5f);
    c[2] = V(0.0f);
    return;
  }
  const V p_len = root(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  const V at_eye = pick(p_len > V(0.0f), V(0.0f), V(1.0f));  // 1 where p is the eye itself
  const V p_inv = pick(p_len > V(0.0f), V(1.0f) / p_len, V(0.0f));
  const V u[3] = {p[0] * p_inv, p[1] * p_inv, p[2] * p_inv - at_eye};
  const V d = nu[0] * u[0] + nu[1] * u[1] + nu[2] * u[2];
  const V r[3] = {u[0] - V(2.0f) * nu[0] * d, u[1] - V(2.0f) * nu[1] * d, u[2] - V(2.0f) * nu[2] * d};
  if (mode == EnvironmentMode::cube) {  // in world space: the room stays put as the camera moves
    for (int k = 0; k < 3; ++k) c[k] = V(to_world[3 * k]) * r[0] + V(to_world[3 * k + 1]) * r[1] + V(to_world[3 * k + 2]) * r[2];
    return;
  }
  const V z1 = r[2] + V(1.0f);
  const V m = V(2.0f) * root(r[0] * r[0] + r[1] * r[1] + z1 * z1);
  const V m_inv = pick(m > V(0.0f), V(1.0f) / m, V(0.0f));
  c[0] = pick(m > V(0.0f), r[0] * m_inv + V(0.5f), V(1.0f));
  c[1] = pick(m > V(0.0f), r[1] * m_inv + V(0.5f), V(0.5f));
  c[2] = V(0.0f);
}

// A cube map's face and (s, t) for direction r (GL 2.1 §3.8.6, table 3.21): the major axis picks
// the face (ties: x before y before z; +X, -X, +Y, -Y, +Z, -Z = 0..5), s = (sc / |ma| + 1) / 2,
// and GL's t = (tc / |ma| + 1) / 2 counted from the top of the face's picture (GL reads faces
// uploaded top row first), so facet's t (from the bottom) is 1 minus it. A zero r reads the +X
// face's centre.
template <class V>
[[gnu::always_inline]] inline void cube_face(const V (&r)[3], V& face, V& s, V& t) {
  const V ax = pick(r[0] < V(0.0f), V(0.0f) - r[0], r[0]), ay = pick(r[1] < V(0.0f), V(0.0f) - r[1], r[1]);
  const V az = pick(r[2] < V(0.0f), V(0.0f) - r[2], r[2]);
  const auto x_major = lane_and(ax >= ay, ax >= az);
  const auto y_major = lane_and(lane_not(x_major), ay >= az);
  // Per face: sc, tc (table 3.21).
  const V sc = pick(x_major, pick(r[0] >= V(0.0f), V(0.0f) - r[2], r[2]), pick(y_major, r[0], pick(r[2] >= V(0.0f), r[0], V(0.0f) - r[0])));
  const V tc = pick(y_major, pick(r[1] >= V(0.0f), r[2], V(0.0f) - r[2]), V(0.0f) - r[1]);
  const V ma = pick(x_major, ax, pick(y_major, ay, az));
  face = pick(x_major, pick(r[0] >= V(0.0f), V(0.0f), V(1.0f)),
              pick(y_major, pick(r[1] >= V(0.0f), V(2.0f), V(3.0f)), pick(r[2] >= V(0.0f), V(4.0f), V(5.0f))));
  const V inv = pick(ma > V(0.0f), V(1.0f) / ma, V(0.0f));
  s = V(0.5f) * (sc * inv + V(1.0f));
  t = V(0.5f) * (V(1.0f) - tc * inv);  // GL's t runs down a face's picture; facet's t = 0 is a picture's bottom
}

// The environment's colour E (RGB) at coordinates c (environment_coords, or their interpolation):
// sample(sampler, s, t, rgba) reads a map at level 0. A cube map reads each face its lanes need.
template <class V, class Sample>
[[gnu::always_inline]] inline void environment_colour(const Draw& d, const V (&c)[3], const Sample& sample, V (&e)[3]) {
  V rgba[4];
  if (d.environment != EnvironmentMode::cube) {
    sample(*d.environment_map[0], c[0], c[1], rgba);
    for (int k = 0; k < 3; ++k) e[k] = rgba[k];
    return;
  }
  V face, s, t;
  cube_face(c, face, s, t);
  for (int k = 0; k < 3; ++k) e[k] = V(0.0f);
  for (int f = 0; f < 6; ++f) {
    const auto on = face == V(static_cast<float>(f));
    if (!any_lane(on)) continue;
    sample(*d.environment_map[f], s, t, rgba);
    for (int k = 0; k < 3; ++k) e[k] = pick(on, rgba[k], e[k]);
  }
}

// The environment stage: E combined with the textured colour c (alpha unchanged) as the draw's
// blend says, strength k: add c + k E (saturated), modulate c (1 - k + k E), mix c (1 - k) + k E.
template <class V>
[[gnu::always_inline]] inline void apply_environment(const Draw& d, const V* e, V (&c)[4]) {
  const V k(d.environment_strength), keep = V(1.0f) - k;
  for (int ch = 0; ch < 3; ++ch) {
    switch (d.environment_blend) {
      case EnvironmentBlend::modulate: c[ch] = c[ch] * (keep + k * e[ch]); break;
      case EnvironmentBlend::mix: c[ch] = c[ch] * keep + k * e[ch]; break;
      default: c[ch] = finish(c[ch] + k * e[ch], d.clamp); break;
    }
  }
}

// --- The surface program's tail: the stages after lighting ------------------------------------

// What the tail reads besides the lit colours: the inputs computed before lighting (the texel,
// null when untextured; the emission added after the texture environment, null when none; the
// fog factor) and what the stages look up per pixel: the varyings generated per vertex for them
// (interpolated; read_tail_varyings) or, lit per pixel, the eye-space position and normal.
template <class V>
struct TailInputs {
  const V* texel = nullptr;
  const V* emitted = nullptr;
  V fog = V(1.0f);
  const V* environment = nullptr;  // Varying::environment interpolated; null: generated from position and normal
  const V* position = nullptr;     // eye space, per pixel (Phong)
  const V* normal = nullptr;
  const V* environment_offset = nullptr;  // flat, Gouraud: a bump map's move of the 2D environment coordinates
};

// A varying of raster::kGeneratedVaryings at a vertex with eye-space position p and normal n,
// into out (width_of(v) floats): the environment map's texgen coordinates.
inline void generate_at_vertex(const Draw& d, raster::Varying v, const float (&p)[3], const float (&n)[3], float* out) {
  if (v == raster::Varying::environment) {
    float c[3];
    environment_coords(d.environment, d.environment_to_world, p, n, c);
    for (int k = 0; k < 3; ++k) out[k] = c[k];
  }
}

// The height map's differences over one level-0 texel at the pixel, (h(u + du) - h(u), h(v + dv)
// - h(v)) of its red channel, times bump_scale (Draw::bump_map): sample(sampler, du, dv, rgba)
// samples a map at the pixel's texture coordinates moved by (du, dv), with the pixel's LOD.
template <class V, class Sample>
[[gnu::always_inline]] inline void bump_slopes(const Draw& d, const Sample& sample, V& su, V& sv) {
  V h0[4], hu[4], hv[4];
  sample(*d.bump_map, 0.0f, 0.0f, h0);
  sample(*d.bump_map, d.bump_du, 0.0f, hu);
  sample(*d.bump_map, 0.0f, d.bump_dv, hv);
  const V k(d.bump_scale);
  su = k * (hu[0] - h0[0]);
  sv = k * (hv[0] - h0[0]);
}

// The normal a pixel lit per pixel (Phong) is lit with: the interpolated eye-space normal
// (value(a) interpolates attribute a), perturbed by the draw's normal and bump maps.
// sample(sampler, du, dv, rgba) samples a map at the pixel's texture coordinates moved by (du,
// dv); bitangent_negative: the triangle's tangent frame is mirrored
// (ScreenTriangle::bitangent_negative).
//
// In the frame of the interpolated normal N and tangent T, neither normalised, the bitangent
// B = w cross(N, T), the tangent-space normal m becomes
//   n = m.x T + m.y B + m.z N,
// MikkTSpace's pixel-shader rule (its tangents are baked for exactly that frame); the lighting
// normalises n. The normal map gives m = 2 rgb - 1 with x and y times normal_scale, the bump map
// (Blinn 1978, as a normal map made from the height's slopes) subtracts its slopes from m.x and
// m.y (m = (-su, -sv, 1) alone). A zero tangent (a degenerate uv triangle) leaves m.z N.
template <class V, class Value, class Sample>
[[gnu::always_inline]] inline void pixel_normal(const Draw& d, const Value& value, bool bitangent_negative,
                                                const Sample& sample, V (&n)[3]) {
  const int a = d.layout.at(raster::Varying::normal);
  for (int c = 0; c < 3; ++c) n[c] = value(a + c);
  if (!d.normal_map && !d.bump_map) return;
  const int ta = d.layout.at(raster::Varying::tangent);
  const V t[3] = {value(ta), value(ta + 1), value(ta + 2)};
  const V w(bitangent_negative ? -1.0f : 1.0f);
  const V b[3] = {w * (n[1] * t[2] - n[2] * t[1]), w * (n[2] * t[0] - n[0] * t[2]), w * (n[0] * t[1] - n[1] * t[0])};
  V mx(0.0f), my(0.0f), mz(1.0f);
  if (d.normal_map) {
    V rgba[4];
    sample(*d.normal_map, 0.0f, 0.0f, rgba);
    const V k(d.normal_scale);
    mx = (V(2.0f) * rgba[0] - V(1.0f)) * k, my = (V(2.0f) * rgba[1] - V(1.0f)) * k, mz = V(2.0f) * rgba[2] - V(1.0f);
  }
  if (d.bump_map) {
    V su, sv;
    bump_slopes(d, sample, su, sv);
    mx = mx - su, my = my - sv;
  }
  for (int c = 0; c < 3; ++c) n[c] = mx * t[c] + my * b[c] + mz * n[c];
}

// A per-pixel draw's ambient occlusion (Draw::occlusion_map): 1 + strength (r - 1), r the map's
// red channel at the pixel (sample(sampler, rgba)); 1 without a map.
template <class V, class Sample>
[[gnu::always_inline]] inline V occlusion(const Draw& d, const Sample& sample) {
  if (!d.occlusion_map) return V(1.0f);
  V rgba[4];
  sample(*d.occlusion_map, rgba);
  return V(1.0f) + V(d.occlusion_strength) * (rgba[0] - V(1.0f));
}

// A PBR draw's metallic and roughness texel values (Draw::metal_rough_map): blue and green at the
// pixel; 1 and 1 without a map (the factors alone).
template <class V, class Sample>
[[gnu::always_inline]] inline void metal_rough(const Draw& d, const Sample& sample, V& metal, V& rough) {
  if (!d.metal_rough_map) {
    metal = rough = V(1.0f);
    return;
  }
  V rgba[4];
  sample(*d.metal_rough_map, rgba);
  metal = rgba[2], rough = rgba[1];
}

// The varyings generated per vertex for the tail's stages (generate_at_vertex),
// interpolated: value(a) interpolates attribute a; `storage` holds them for `in`.
template <class V, class Value>
[[gnu::always_inline]] inline void read_tail_varyings(const Draw& d, const Value& value, V (&storage)[3], TailInputs<V>& in) {
  const int a = d.layout.at(raster::Varying::environment);
  if (a < 0) return;
  for (int k = 0; k < 3; ++k) storage[k] = value(a + k);
  in.environment = storage;
}

// The values a per-pixel (Phong) surface draw carries from before lighting to its tail (through
// the PhongSink's carry streams), in this order and only those the draw uses: the texel RGBA,
// the emission RGB, the fog factor. carry packs them into out and says how many; uncarry points
// `in` at them again (load(k) reads carried value k into storage).
static_assert(4 + 3 + 1 <= pixel::kMaxCarried, "the sink has a stream for every carried value");
template <class V>
[[gnu::always_inline]] inline int carry(const Draw& d, const Fog& fog, const TailInputs<V>& in, V* out) {
  int n = 0;
  if (d.texture) for (int k = 0; k < 4; ++k) out[n++] = in.texel ? in.texel[k] : V(1.0f);
  if (d.emission) for (int k = 0; k < 3; ++k) out[n++] = in.emitted ? in.emitted[k] : V(0.0f);
  if (fog.mode != FogMode::none) out[n++] = in.fog;
  return n;
}
template <class V, class Load>
[[gnu::always_inline]] inline void uncarry(const Draw& d, const Fog& fog, const Load& load, V (&storage)[pixel::kMaxCarried],
                                           TailInputs<V>& in) {
  int n = 0;
  if (d.texture) {
    in.texel = storage + n;
    for (int k = 0; k < 4; ++k, ++n) storage[n] = load(n);
  }
  if (d.emission) {
    in.emitted = storage + n;
    for (int k = 0; k < 3; ++k, ++n) storage[n] = load(n);
  }
  if (fog.mode != FogMode::none) in.fog = load(n);
}

// One fragment's colour (c[0..2]) and alpha (c[3]) from its primary colour p, secondary colour s
// (null: the specular is in p; Draw::separate_specular) and alpha a: the texture environment,
// the environment map, the emission, the colour sum, fog. level0(sampler, s, t, rgba) samples a
// map at level 0. kPerPixel: lit per pixel (the stages may look up the eye-space position and
// normal); otherwise only the interpolated varyings (the per-vertex programs carry none of the
// per-pixel stages' code).
template <bool kPerPixel, class V, class Sample>
[[gnu::always_inline]] inline void surface_colour(const Draw& d, const Fog& fog, const V (&p)[3], const V* s, const V& a,
                                                  const TailInputs<V>& in, const Sample& level0, V (&c)[4]) {
  texture_environment(d, p, a, in.texel, c);
  if (d.environment != EnvironmentMode::none) {
    V coords[3], e[3];
    if constexpr (!kPerPixel) {
      for (int k = 0; k < 3; ++k) coords[k] = in.environment[k];
      if (in.environment_offset) coords[0] = coords[0] + in.environment_offset[0], coords[1] = coords[1] + in.environment_offset[1];
    } else {
      const V position[3] = {in.position[0], in.position[1], in.position[2]};
      const V normal[3] = {in.normal[0], in.normal[1], in.normal[2]};
      environment_coords(d.environment, d.environment_to_world, position, normal, coords);
    }
    environment_colour(d, coords, level0, e);
    apply_environment(d, e, c);
  }
  if (in.emitted) add_colour(d, in.emitted, c);
  if (s) add_colour(d, s, c);
  if (fog.mode != FogMode::none) apply_fog(fog, in.fog, c);
}

// The surface program after coverage, depth and the alpha test: the same stages in the same
// order for the scalar rasterizer (V = float, one fragment) and the SIMD programs (V = a batch).
// The fog factor at clip w `w`, the emission and the lightmap, then either the hand-off to the
// per-pixel lighting (to_phong(in), lit where the gathered pixels are flushed; returns false) or
// the colour c of a fragment lit per vertex (returns true). value(a): varying a at the fragment;
// sample_at(sampler, rgba): a map at the fragment's coordinates with its LOD; sample_moved(sampler,
// du, dv, rgba): the same moved by (du, dv); level0(sampler, s, t, rgba): a map at level 0.
template <class V, class Value, class SampleAt, class SampleMoved, class Level0, class ToPhong>
[[gnu::always_inline]] inline bool surface_tail(const Draw& d, const Fog& fog, ShadingMode shading, const raster::ScreenTriangle& t,
                                                const Value& value, const V& w, const V* texel, const V& alpha,
                                                const SampleAt& sample_at, const SampleMoved& sample_moved, const Level0& level0,
                                                const ToPhong& to_phong, V (&c)[4]) {
  TailInputs<V> in;
  in.texel = texel;
  in.fog = fog.mode != FogMode::none ? fog_factor(fog, w) : V(1.0f);
  V emitted[3];
  if (d.emission) {  // added after the texture environment
    emission(d, sample_at, emitted);
    if (d.lightmap) {  // a lightmapped draw always has the emission stage
      const int lm = d.layout.at(raster::Varying::lightmap_uv);
      const V lu = value(lm), lv = value(lm + 1);
      lightmap_light(d, [&](const texture::Sampler& s, V (&out)[4]) { level0(s, lu, lv, out); }, texel, emitted);
    }
    in.emitted = emitted;
  }
  if (shading == ShadingMode::phong) {
    to_phong(in);
    return false;
  }
  V p[3], sec[3], generated[3], moved[2];
  const V* secondary = vertex_colours(shading, d, t, value, p, sec);
  read_tail_varyings(d, value, generated, in);
  if (d.bump_map && d.environment != EnvironmentMode::none) {  // environment-mapped bump
    bump_slopes(d, sample_moved, moved[0], moved[1]);
    in.environment_offset = moved;
  }
  surface_colour<false>(d, fog, p, secondary, alpha, in, level0, c);
  return true;
}

// The surface program of a pixel lit per pixel, after the lighting kernel: its primary colour p
// and specular s (used when Draw::separate_specular), the eye-space position and normal it was
// lit at, and the tail's inputs carried through the lighting (load(q): carried value q, as
// carry() stored them). The same for the scalar rasterizer's batches and the SIMD Phong sink.
template <class V, class Load, class Level0>
[[gnu::always_inline]] inline void lit_surface_colour(const Draw& d, const Fog& fog, const V (&p)[3], const V (&s)[3],
                                                      const V (&position)[3], const V (&normal)[3], const Load& load,
                                                      const V& alpha, const Level0& level0, V (&c)[4]) {
  V carried[pixel::kMaxCarried];
  TailInputs<V> in;
  in.position = position;
  in.normal = normal;
  uncarry(d, fog, load, carried, in);
  surface_colour<true>(d, fog, p, d.separate_specular ? s : nullptr, alpha, in, level0, c);
}

// The alpha a fragment will have (what the alpha test sees) without computing its colour.
template <class V>
[[gnu::always_inline]] inline V fragment_alpha(const Draw& d, const V& a, const V* t) {
  if (!t) return a;
  if (d.texture_env == TextureMode::replace) return t[3];
  if (d.texture_env == TextureMode::decal) return a;
  return a * t[3];
}

// Alpha to coverage (Draw::alpha_to_coverage): whether sample s of n keeps its coverage at the
// fragment's alpha a. llvmpipe's rule, a > s / n: alpha 0 covers no sample, any alpha above
// (k - 1) / n covers k, 1 covers all; s / n is exact (n is a power of two).
template <class V>
[[gnu::always_inline]] inline auto alpha_covers(const V& a, int s, int n) {
  return a > V(static_cast<float>(s) / static_cast<float>(n));
}

// Blends source c (RGBA) over destination dst (RGBA) with GL's factors (the same for alpha as for
// colour): alpha (SRC_ALPHA, ONE_MINUS_SRC_ALPHA), premultiplied (ONE, ONE_MINUS_SRC_ALPHA), add
// (ONE, ONE), multiply (DST_COLOR, ZERO), subtract (reverse subtract: dst - src); then finish
// (saturated when `clamp`). blend_channel: one channel, the mode fixed at compile time (the fused
// BlendProgram's, which loads, blends and stores a channel at a time); blend_as: all four; blend:
// the draw's mode.
template <BlendMode Mode, class V>
[[gnu::always_inline]] inline V blend_channel(const V& c, const V& a, const V& dst, bool clamp) {
  V out;
  if constexpr (Mode == BlendMode::alpha) {
    out = c * a + dst * (V(1.0f) - a);
  } else if constexpr (Mode == BlendMode::premultiplied) {
    out = c + dst * (V(1.0f) - a);
  } else if constexpr (Mode == BlendMode::add) {
    out = c + dst;
  } else if constexpr (Mode == BlendMode::multiply) {
    out = c * dst;
  } else if constexpr (Mode == BlendMode::subtract) {
    out = dst - c;
  } else {
    out = c;
  }
  return finish(out, clamp);
}
template <BlendMode Mode, class V>
[[gnu::always_inline]] inline void blend_as(const V (&c)[4], V (&dst)[4], bool clamp) {
  for (int k = 0; k < 4; ++k) dst[k] = blend_channel<Mode>(c[k], c[3], dst[k], clamp);
}
template <class V>
[[gnu::always_inline]] inline void blend(const Draw& d, const V (&c)[4], V (&dst)[4]) {
  switch (d.blend) {
    case BlendMode::alpha: return blend_as<BlendMode::alpha>(c, dst, d.clamp);
    case BlendMode::premultiplied: return blend_as<BlendMode::premultiplied>(c, dst, d.clamp);
    case BlendMode::add: return blend_as<BlendMode::add>(c, dst, d.clamp);
    case BlendMode::multiply: return blend_as<BlendMode::multiply>(c, dst, d.clamp);
    case BlendMode::subtract: return blend_as<BlendMode::subtract>(c, dst, d.clamp);
    default: return blend_as<BlendMode::opaque>(c, dst, d.clamp);
  }
}

}  // namespace
}  // namespace facet::pixel
