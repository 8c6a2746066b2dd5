// Internal: a PBR material's colour (pbr_shade.hpp's model: the glTF BRDF under the lights, the
// surroundings by split sum) on xsimd batches, one point per float lane: the SIMD twin of
// shade_pbr<float>, which is its oracle (tests/pbr_simd_test.cpp, every ISA). Included only by the
// per-ISA files shade_simd_<isa>.cpp; everything is a template on Arch.
//
// Where it departs from the scalar twin (each inside the bound the test states):
//  - the non-exact tiers normalise, divide and take Smith's square roots with the hardware's
//    estimates and one Newton step (relative 2^-22, as the classic kernel); the exact tier uses
//    IEEE sqrt and division, in float lanes (the image light's tables are float: double lanes would
//    carry no more of them);
//  - the spot exponent's pow is the tier's method (as the classic kernel's);
//  - the image light's texels are gathered (avx2, avx512; element loads on sse2) at the same
//    bilinear and between-level weights as image_light.hpp's lookups; the texel indices are
//    formed in float, exact because the largest (the levels' floats, about 4e5) is below 2^24.
#pragma once

#include <cstdint>

#include "common/gather_simd.hpp"
#include "lighting/shade_simd.hpp"

namespace facet::lighting::simd {

// base[index] in every lane; `index` holds whole numbers in [0, 2^24).
template <class B>
[[gnu::always_inline]] inline B gather_float(const float* base, const B& index) {
  const auto i = xsimd::to_int(index);
  return xsimd::bitwise_cast<B>(simd_util::gather32<typename B::arch_type>(reinterpret_cast<const std::int32_t*>(base), i));
}

// Linear interpolation a + (b - a) f, written as the scalar lookups write it.
template <class B>
[[gnu::always_inline]] inline B mix(const B& a, const B& b, const B& f) {
  return a + (b - a) * f;
}

// x n - 1/2 held in [0, n - 1] (NaN -> 0), its cell i <= n - 2 and the fraction past it: a
// bilinear coordinate over n >= 2 texels (image_light.hpp's face_bilinear and dfg).
template <class B>
[[gnu::always_inline]] inline void cell(const B& x, const B& n, B& i, B& f) {
  B c = x * n - B(0.5f);
  c = xsimd::select(c > B(0.0f), xsimd::select(c < n - B(1.0f), c, n - B(1.0f)), B(0.0f));
  i = xsimd::min(xsimd::floor(c), n - B(2.0f));
  f = c - i;
}

// The split sum's scale and bias of f0 and f90 at (n.v, roughness), from the DFG table.
template <class B>
[[gnu::always_inline]] inline void dfg_lookup(const float* table, const B& n_dot_v, const B& roughness, B& scale, B& bias) {
  const B size = B(static_cast<float>(kDfgSize));
  B i, j, s, t;
  cell(n_dot_v, size, i, s);
  cell(roughness, size, j, t);
  const B at = B(2.0f) * xsimd::fma(j, size, i);
  const B row(float(2 * kDfgSize));
  const B c00 = gather_float(table, at), c10 = gather_float(table, at + B(2.0f));
  const B c01 = gather_float(table, at + row), c11 = gather_float(table, at + row + B(2.0f));
  scale = mix(mix(c00, c10, s), mix(c01, c11, s), t);
  const B d00 = gather_float(table, at + B(1.0f)), d10 = gather_float(table, at + B(3.0f));
  const B d01 = gather_float(table, at + row + B(1.0f)), d11 = gather_float(table, at + row + B(3.0f));
  bias = mix(mix(d00, d10, s), mix(d01, d11, s), t);
}

// Irradiance / pi at the unit environment-space normal n from the harmonics, >= 0 (ImageLight::diffuse).
template <class B>
[[gnu::always_inline]] inline V<B> sh_diffuse(const ImageView& im, const V<B>& n) {
  const B y9[9] = {B(1.0f), n.y, n.z, n.x, n.x * n.y, n.y * n.z, B(3.0f) * n.z * n.z - B(1.0f), n.x * n.z, n.x * n.x - n.y * n.y};
  B out[3];
  for (int c = 0; c < 3; ++c) {
    B e(0.0f);
    for (int k = 0; k < 9; ++k) e += B(im.sh[c][k]) * y9[k];
    out[c] = xsimd::select(e > B(0.0f), e, B(0.0f));
  }
  return {out[0], out[1], out[2]};
}

// A cube direction's face (as a float 0..5) and face coordinates in [0, 1] (image_light.hpp's cube_face).
template <class B>
[[gnu::always_inline]] inline void cube_coordinates(const V<B>& r, B& face, B& s, B& t) {
  const B zero(0.0f);
  const B ax = xsimd::abs(r.x), ay = xsimd::abs(r.y), az = xsimd::abs(r.z);
  const auto on_x = (ax >= ay) && (ax >= az);
  const auto on_y = !on_x && (ay >= az);
  const auto px = r.x > zero, py = r.y > zero, pz = r.z > zero;
  face = xsimd::select(on_x, xsimd::select(px, B(0.0f), B(1.0f)),
                       xsimd::select(on_y, xsimd::select(py, B(2.0f), B(3.0f)), xsimd::select(pz, B(4.0f), B(5.0f))));
  const B sc = xsimd::select(on_x, xsimd::select(px, -r.z, r.z), xsimd::select(on_y, r.x, xsimd::select(pz, r.x, -r.x)));
  const B tc = xsimd::select(on_y, xsimd::select(py, r.z, -r.z), -r.y);
  const B ma = xsimd::select(on_x, ax, xsimd::select(on_y, ay, az));
  const B inv = xsimd::select(ma > zero, B(1.0f) / xsimd::select(ma > zero, ma, B(1.0f)), zero);
  s = B(0.5f) * xsimd::fma(sc, inv, B(1.0f));
  t = B(0.5f) * xsimd::fma(tc, inv, B(1.0f));
}

// Bilinear at (s, t) of `face` in the level whose faces are n texels a side, starting at float
// `offset` of the radiance array.
template <class B>
[[gnu::always_inline]] inline V<B> level_bilinear(const float* radiance, const B& offset, const B& n, const B& face,
                                                  const B& s, const B& t) {
  B i, j, fs, ft;
  cell(s, n, i, fs);
  cell(t, n, j, ft);
  const B at = xsimd::fma(B(3.0f), xsimd::fma(xsimd::fma(face, n, j), n, i), offset);
  const B row = B(3.0f) * n;
  B out[3];
  for (int c = 0; c < 3; ++c) {
    const B t00 = at + B(float(c)), t01 = t00 + row;
    const B a = mix(gather_float(radiance, t00), gather_float(radiance, t00 + B(3.0f)), fs);
    const B b = mix(gather_float(radiance, t01), gather_float(radiance, t01 + B(3.0f)), fs);
    out[c] = mix(a, b, ft);
  }
  return {out[0], out[1], out[2]};
}

// The radiance prefiltered for `roughness` around the unit environment-space direction r, read
// linearly between the two levels around it (ImageLight::specular).
template <class B>
[[gnu::always_inline]] inline V<B> prefiltered(const ImageView& im, const V<B>& r, const B& roughness) {
  constexpr float top = float(kRadianceLevels - 1);
  B level = roughness * B(top);
  level = xsimd::select(level > B(0.0f), xsimd::select(level < B(top), level, B(top)), B(0.0f));
  const B k = xsimd::min(xsimd::floor(level), B(top - 1.0f));
  const B f = level - k;
  B offset0(0.0f), size0(0.0f), offset1(0.0f), size1(0.0f);
  for (int m = 0; m < kRadianceLevels; ++m) {
    const auto here = k == B(float(m)), below = k == B(float(m - 1));
    offset0 = xsimd::select(here, B(float(im.offset[m])), offset0), size0 = xsimd::select(here, B(float(im.size[m])), size0);
    offset1 = xsimd::select(below, B(float(im.offset[m])), offset1), size1 = xsimd::select(below, B(float(im.size[m])), size1);
  }
  B face, s, t;
  cube_coordinates(r, face, s, t);
  const V<B> a = level_bilinear(im.radiance, offset0, size0, face, s, t);
  const V<B> b = level_bilinear(im.radiance, offset1, size1, face, s, t);
  return {mix(a.x, b.x, f), mix(a.y, b.y, f), mix(a.z, b.z, f)};
}

// The PBR kernel: shade_pbr<float>'s terms, in the same order (see pbr_shade.hpp for the model).
template <class Arch, bool Exact>
void shade_pbr_kernel(const Params& prm, const Transform* xf, const Streams& s) {
  using B = xsimd::batch<float, Arch>;
  constexpr std::size_t lanes = B::size;
  const PbrParams& q = prm.pbr;
  const ImageView& im = q.image;
  const B zero(0.0f), one(1.0f);
  // sqrt(x) for x > 0 and a / b for b in [1e-12, FLT_MAX]: IEEE on the exact tier, else estimates.
  auto root = [](const B& x) {
    if constexpr (Exact) return xsimd::sqrt(x);
    else return x * rsqrt_nr(x);
  };
  auto over = [](const B& a, const B& b) {
    if constexpr (Exact) return a / b;
    else return a * rcp_nr(b);
  };
  const bool triples = s.p3 != nullptr;
  auto read3 = [&](const float* src, std::size_t i) { return read_triples<B>(src, i, s.count); };
  auto write3 = [&](float* dst, std::size_t i, const B& x, const B& y, const B& z) { write_triples(dst, i, s.count, x, y, z); };
  const float* m = xf ? xf->position : nullptr;
  const float* nm = xf ? xf->normal : nullptr;
  const float* te = q.to_env;
  const bool textured = q.metal_rough && s.pm && s.pr;
  for (std::size_t i = 0; i < s.count; i += lanes) {
    V<B> p, n;
    load_point(s, i, m, nm, p, n);
    // The point's metallic and roughness: the factors, times the texels of a metallic-roughness map.
    B metal(q.metallic), roughness(q.roughness), alpha(q.alpha);
    if (textured) {
      metal = fastmath::clamp01(B(q.metallic) * B::load_unaligned(s.pm + i));
      const B r = B(q.roughness_factor) * B::load_unaligned(s.pr + i);
      roughness = xsimd::select(r > B(0.045f), xsimd::select(r < one, r, one), B(0.045f));  // NaN -> 0.045
      alpha = roughness * roughness;
    }
    const B ao = prm.occlusion && s.ao ? B::load_unaligned(s.ao + i) : one;
    n = normalize_or_zero<Exact>(n);
    const V<B> v = prm.local_viewer ? normalize_or_zero<Exact>(V<B>{-p.x, -p.y, -p.z}) : V<B>{zero, zero, one};
    B c[3] = {B(q.base_color[0]), B(q.base_color[1]), B(q.base_color[2])};
    if (prm.color_material) {
      const V<B> albedo = triples ? read3(s.a3, i)
                                  : V<B>{B::load_unaligned(s.ar + i), B::load_unaligned(s.ag + i), B::load_unaligned(s.ab + i)};
      c[0] *= albedo.x, c[1] *= albedo.y, c[2] *= albedo.z;
    }
    const B dielectric = one - metal;
    B x[3] = {zero, zero, zero}, y[3] = {zero, zero, zero};
    B surround[3] = {B(q.ambient[0]), B(q.ambient[1]), B(q.ambient[2])};
    const auto lit = dot3(n, n) > zero;  // a unit normal, not the zero of a degenerate one
    const B v_along_n = dot3(n, v);
    const B n_dot_v = xsimd::select(v_along_n > B(1e-4f), xsimd::select(v_along_n < one, v_along_n, one), B(1e-4f));
    const B a2 = alpha * alpha, one_less_a2 = one - a2;
    const B smith_v = root(xsimd::fma(n_dot_v * n_dot_v, one_less_a2, a2));  // >= alpha > 0
    for (int li = 0; li < prm.light_count; ++li) {
      const EyeLight<float>& L = prm.lights[li];
      B att;
      const V<B> l = light_vector<Exact, true>(L, p, att);
      surround[0] = xsimd::fma(att, B(L.ambient.x), surround[0]);
      surround[1] = xsimd::fma(att, B(L.ambient.y), surround[1]);
      surround[2] = xsimd::fma(att, B(L.ambient.z), surround[2]);
      const B n_dot_l = dot3(n, l);
      const auto facing = n_dot_l > zero;  // false for NaN
      if (!xsimd::any(facing)) continue;
      B k = att * n_dot_l;
      if (L.shadow >= 0 && s.visibility) k *= B::load_unaligned(s.visibility[L.shadow] + i);
      B e[3] = {k * B(L.diffuse.x), k * B(L.diffuse.y), k * B(L.diffuse.z)};
      if (L.projector >= 0 && s.projector) {
        for (int ch = 0; ch < 3; ++ch) e[ch] *= B::load_unaligned(s.projector[3 * L.projector + ch] + i);
      }
      const V<B> h = normalize_or_zero<Exact>(V<B>{l.x + v.x, l.y + v.y, l.z + v.z});
      const B n_dot_h = fastmath::clamp01(dot3(n, h)), v_dot_h = fastmath::clamp01(dot3(v, h));
      // D V: GGX and the height-correlated Smith term; lanes not facing the light are dropped below.
      // GGX's denominator as |n x h|^2 + (n.h)^2 a^2 (pbr_shade.hpp), 1 without a half vector.
      const V<B> nxh{n.y * h.z - n.z * h.y, n.z * h.x - n.x * h.z, n.x * h.y - n.y * h.x};
      const B g = xsimd::select(dot3(h, h) > B(0.5f), xsimd::fma(n_dot_h * n_dot_h, a2, dot3(nxh, nxh)), one);
      const B d = over(a2 * B(0.31830988618379067f), g * g);
      const B gv = n_dot_l * smith_v;
      const B gl = n_dot_v * root(xsimd::select(facing, xsimd::fma(n_dot_l * n_dot_l, one_less_a2, a2), one));
      const B dv = d * over(B(0.5f), xsimd::select(facing, gv + gl, one));
      const B s1 = one - v_dot_h, s2 = s1 * s1, s5 = s2 * s2 * s1;  // Schlick's (1 - v.h)^5
      for (int ch = 0; ch < 3; ++ch) {
        const B fd = xsimd::fma(B(q.f90 - q.f0[ch]), s5, B(q.f0[ch]));
        const B xs = e[ch] * (dielectric * (one - fd) * B(0.31830988618379067f) + metal * (one - s5) * dv);
        const B ys = e[ch] * (dielectric * fd * dv + metal * s5 * dv);
        x[ch] += xsimd::select(facing, xs, zero);
        y[ch] += xsimd::select(facing, ys, zero);
      }
    }
    // The surroundings, split-sum.
    B ld[3], ls[3];
    for (int ch = 0; ch < 3; ++ch) ld[ch] = ls[ch] = xsimd::select(lit, surround[ch], zero);
    if (im.has_image && xsimd::any(lit)) {
      const V<B> nw{B(te[0]) * n.x + B(te[1]) * n.y + B(te[2]) * n.z, B(te[3]) * n.x + B(te[4]) * n.y + B(te[5]) * n.z,
                    B(te[6]) * n.x + B(te[7]) * n.y + B(te[8]) * n.z};
      // The mirror direction turned towards the normal as the lobe widens (pbr_shade.hpp).
      const B two = v_along_n + v_along_n;
      const V<B> re{two * n.x - v.x + alpha * (n.x - two * n.x + v.x), two * n.y - v.y + alpha * (n.y - two * n.y + v.y),
                    two * n.z - v.z + alpha * (n.z - two * n.z + v.z)};
      const V<B> rw{B(te[0]) * re.x + B(te[1]) * re.y + B(te[2]) * re.z, B(te[3]) * re.x + B(te[4]) * re.y + B(te[5]) * re.z,
                    B(te[6]) * re.x + B(te[7]) * re.y + B(te[8]) * re.z};
      const V<B> diffuse = sh_diffuse(im, nw);
      const V<B> specular = prefiltered(im, normalize_or_zero<Exact>(rw), roughness);
      const B in(q.intensity);
      ld[0] = xsimd::select(lit, xsimd::fma(in, diffuse.x, ld[0]), ld[0]);
      ld[1] = xsimd::select(lit, xsimd::fma(in, diffuse.y, ld[1]), ld[1]);
      ld[2] = xsimd::select(lit, xsimd::fma(in, diffuse.z, ld[2]), ld[2]);
      ls[0] = xsimd::select(lit, xsimd::fma(in, specular.x, ls[0]), ls[0]);
      ls[1] = xsimd::select(lit, xsimd::fma(in, specular.y, ls[1]), ls[1]);
      ls[2] = xsimd::select(lit, xsimd::fma(in, specular.z, ls[2]), ls[2]);
    }
    B scale, bias;
    dfg_lookup(im.dfg, n_dot_v, roughness, scale, bias);
    const B ess = scale + bias, ems = one - ess;
    B mms[3];
    for (int ch = 0; ch < 3; ++ch) {
      // Dielectric layer: f0 and f90 do not depend on c.
      const B f0(q.f0[ch]), f90(q.f90);
      const B fss = xsimd::fma(f0, scale, f90 * bias);
      const B favg(q.f0[ch] + (q.f90 - q.f0[ch]) * float(1.0 / 21.0));
      const B fms = over(fss * favg * ems, one - ems * favg);
      x[ch] += ao * dielectric * (one - fss - fms) * ld[ch];
      y[ch] += ao * dielectric * (fss * ls[ch] + fms * ld[ch]);
      // Metal layer: f0 = c, f90 = 1.
      const B mavg = xsimd::fma(one - c[ch], B(float(1.0 / 21.0)), c[ch]);
      const B mss = xsimd::fma(c[ch], scale, bias);
      mms[ch] = ao * metal * over(mss * mavg * ems, one - ems * mavg) * ld[ch];
      x[ch] += ao * metal * scale * ls[ch];
      y[ch] += ao * metal * bias * ls[ch];
    }
    B r = xsimd::fma(c[0], x[0], B(prm.base[0]) + mms[0]);
    B gg = xsimd::fma(c[1], x[1], B(prm.base[1]) + mms[1]);
    B b = xsimd::fma(c[2], x[2], B(prm.base[2]) + mms[2]);
    if (prm.separate_specular) {
      if (triples) {
        write3(s.spec3, i, finish(prm, y[0]), finish(prm, y[1]), finish(prm, y[2]));
      } else {
        finish(prm, y[0]).store_unaligned(s.sr + i);
        finish(prm, y[1]).store_unaligned(s.sg + i);
        finish(prm, y[2]).store_unaligned(s.sb + i);
      }
    } else {
      r += y[0], gg += y[1], b += y[2];
    }
    if (triples) {
      write3(s.rgb3, i, finish(prm, r), finish(prm, gg), finish(prm, b));
    } else {
      finish(prm, r).store_unaligned(s.r + i);
      finish(prm, gg).store_unaligned(s.g + i);
      finish(prm, b).store_unaligned(s.b + i);
    }
  }
}

// Every material: the PBR kernel for a PBR material, else the classic one.
template <class Arch>
void shade_any(const Params& prm, const Transform* xf, const Streams& s) {
  if (!prm.pbr.on) return shade_streams<Arch>(prm, xf, s);
  if (prm.exact_math) return shade_pbr_kernel<Arch, true>(prm, xf, s);
  shade_pbr_kernel<Arch, false>(prm, xf, s);
}

}  // namespace facet::lighting::simd
