// Internal: a PBR material's colour at one point (Material::model == pbr), the glTF 2.0 BRDF of
// pbr.hpp under the scene's lights and surroundings, written once for double (the reference
// path) and float (the scalar path; for now also what the SIMD path runs for PBR draws).
//
//   colour = e + sum over lights of E_i (n.l) f(l, v)                       (punctual)
//          + o [c_diff (1 - Fss Ess - Fms Ems) L_d + Fss Ess L_s + Fms Ems L_d]   (surroundings)
//
// with E_i = pi d_i att_i spot_i (a light's diffuse colour d_i is the radiance a white
// Lambertian surface facing it shows), o the ambient occlusion, and the surroundings (`ambient`
// is the scene's global ambient when it has no environment picture, else 0)
//   L_d = ambient + sum of att_i spot_i a_i + intensity SH irradiance(n) / pi      (diffuse)
//   L_s = ambient + sum of att_i spot_i a_i + intensity prefiltered(r', roughness) (specular)
// where r' = normalize(mix(r, n, roughness^2)) is the mirror direction r turned towards the normal,
// the split sum's Fss Ess = f0 A + f90 B from the DFG table and Fdez-Aguera's multiple
// scattering Fms Ems = Fss Ess F_avg (1 - A - B) / (1 - (1 - A - B) F_avg), per layer
// (dielectric: f0 from ior and KHR_materials_specular, f90 the specular weight; metal: f0 the
// base colour, f90 1), mixed by metallic as the BRDF is. n.v is held at >= 1e-4 (a normal
// turned slightly away from the eye, as interpolated normals at a silhouette are, still sees
// its highlight's edge).
//
// With separate specular (a base colour texture), the colour is split so that the texel t
// multiplies the first part: primary = c (X) + M, secondary = Y, where c X holds every term
// linear in the base colour, Y every term without it, and M the metal's multiple scattering
// (not linear in c: evaluated for the base colour factor and scaled by t with the rest, exact
// when t = 1; docs/pbr.md).
#pragma once

#include <cmath>

#include "lighting/image_light.hpp"
#include "lighting/shade.hpp"

namespace facet::lighting {

template <class T>
V3<T> shade_pbr(const ShadeParams<T>& sp, V3<T> p, V3<T> n_in, V3<T> albedo, V3<T>* secondary, const float* visibility,
                T occlusion, const float* projector, const float* metal_rough) {
  const PbrTerms<T>& q = sp.pbr;
  // The point's metallic and roughness: the factors, times the texels of a metallic-roughness map.
  T metal = q.metallic, roughness = q.roughness, alpha = q.alpha;
  if (sp.metal_rough && metal_rough) {
    metal = clamp01(q.metallic * T(metal_rough[0]));
    const T r = q.roughness_factor * T(metal_rough[1]);
    roughness = r > T(0.045) ? (r < T(1) ? r : T(1)) : T(0.045);  // pbr::kMinRoughness; NaN -> 0.045
    alpha = roughness * roughness;
  }
  if (!sp.occlusion) occlusion = T(1);  // (callers may pass any value when the draw has no occlusion map)
  const V3<T> n = normalize_or_zero(n_in);
  const V3<T> v = sp.local_viewer ? normalize_or_zero(V3<T>{-p.x, -p.y, -p.z}) : V3<T>{T(0), T(0), T(1)};
  const T c[3] = {q.base_color.x * (sp.color_material ? albedo.x : T(1)),
                  q.base_color.y * (sp.color_material ? albedo.y : T(1)),
                  q.base_color.z * (sp.color_material ? albedo.z : T(1))};
  const T dielectric = T(1) - metal;
  const T f0[3] = {q.f0.x, q.f0.y, q.f0.z};
  T x[3] = {T(0), T(0), T(0)}, y[3] = {T(0), T(0), T(0)}, m[3] = {T(0), T(0), T(0)};
  T surround[3] = {q.ambient.x, q.ambient.y, q.ambient.z};  // uniform radiance
  const bool lit = n.x != T(0) || n.y != T(0) || n.z != T(0);
  T n_dot_v = dot(n, v);
  n_dot_v = n_dot_v > T(1e-4) ? (n_dot_v < T(1) ? n_dot_v : T(1)) : T(1e-4);
  const T a2 = alpha * alpha;
  for (const EyeLight<T>& L : sp.lights) {
    V3<T> l;
    T att;
    if (!light_at(L, p, l, att)) continue;
    surround[0] += att * L.ambient.x, surround[1] += att * L.ambient.y, surround[2] += att * L.ambient.z;
    const T n_dot_l = dot(n, l);
    if (!(n_dot_l > T(0))) continue;
    T e[3] = {att * n_dot_l * L.diffuse.x, att * n_dot_l * L.diffuse.y, att * n_dot_l * L.diffuse.z};
    if (L.shadow >= 0 && visibility) {
      const T vis = T(visibility[L.shadow]);
      for (T& k : e) k *= vis;
    }
    if (L.projector >= 0 && projector) {
      const float* f = projector + 3 * L.projector;
      for (int k = 0; k < 3; ++k) e[k] *= T(f[k]);
    }
    const V3<T> h = normalize_or_zero(l + v);
    const T n_dot_h = clamp01(dot(n, h)), v_dot_h = clamp01(dot(v, h));
    // D V: GGX and the height-correlated Smith term (pbr::ggx_d, pbr::smith_v). GGX's
    // denominator 1 - (n.h)^2 (1 - a^2) as |n x h|^2 + (n.h)^2 a^2, which keeps its relative
    // accuracy at the peak of a narrow lobe, where 1 - (n.h)^2 cancels (Filament's form); 1
    // where there is no half vector (l = -v).
    const V3<T> nxh{n.y * h.z - n.z * h.y, n.z * h.x - n.x * h.z, n.x * h.y - n.y * h.x};
    const T k = dot(h, h) > T(0.5) ? dot(nxh, nxh) + n_dot_h * n_dot_h * a2 : T(1);
    const T d = a2 / (T(3.14159265358979323846) * k * k);
    const T gv = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (T(1) - a2) + a2);
    const T gl = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (T(1) - a2) + a2);
    const T dv = d * (T(0.5) / (gv + gl));
    const T s1 = T(1) - v_dot_h, s2 = s1 * s1, s = s2 * s2 * s1;  // Schlick's (1 - v.h)^5
    for (int ch = 0; ch < 3; ++ch) {
      const T fd = f0[ch] + (q.f90 - f0[ch]) * s;
      x[ch] += e[ch] * (dielectric * (T(1) - fd) * T(0.31830988618379067) + metal * (T(1) - s) * dv);
      y[ch] += e[ch] * (dielectric * fd * dv + metal * s * dv);
    }
  }
  if (!lit) {  // no normal: the emission alone (as the classic model gives a zero normal no diffuse light)
    for (T& k : surround) k = T(0);
  }
  // The surroundings, split-sum.
  T ld[3] = {surround[0], surround[1], surround[2]}, ls[3] = {surround[0], surround[1], surround[2]};
  if (lit && q.image && q.image->has_image()) {
    const T* r = q.to_env;
    const V3<T> nw{r[0] * n.x + r[1] * n.y + r[2] * n.z, r[3] * n.x + r[4] * n.y + r[5] * n.z,
                   r[6] * n.x + r[7] * n.y + r[8] * n.z};
    // The mirror direction turned towards the normal as the lobe widens (the lobe's dominant
    // direction: three.js mixes by roughness^2 as here; Filament likewise), which keeps rough
    // surfaces from gathering light from behind their tangent plane.
    const T two = T(2) * dot(n, v);
    const V3<T> re{two * n.x - v.x + alpha * (n.x - two * n.x + v.x), two * n.y - v.y + alpha * (n.y - two * n.y + v.y),
                   two * n.z - v.z + alpha * (n.z - two * n.z + v.z)};
    const V3<T> rw{r[0] * re.x + r[1] * re.y + r[2] * re.z, r[3] * re.x + r[4] * re.y + r[5] * re.z,
                   r[6] * re.x + r[7] * re.y + r[8] * re.z};
    const V3<T> diffuse = q.image->diffuse(nw), specular = q.image->specular(normalize_or_zero(rw), roughness);
    ld[0] += q.intensity * diffuse.x, ld[1] += q.intensity * diffuse.y, ld[2] += q.intensity * diffuse.z;
    ls[0] += q.intensity * specular.x, ls[1] += q.intensity * specular.y, ls[2] += q.intensity * specular.z;
  }
  if (lit && q.image) {
    T scale, bias;
    q.image->dfg(n_dot_v, roughness, scale, bias);
    const T ess = scale + bias, ems = T(1) - ess;
    for (int ch = 0; ch < 3; ++ch) {
      // Dielectric layer: f0 and f90 do not depend on c.
      const T fss = f0[ch] * scale + q.f90 * bias;
      const T favg = f0[ch] + (q.f90 - f0[ch]) * T(1.0 / 21.0);
      const T fms = fss * favg * ems / (T(1) - ems * favg);
      x[ch] += occlusion * dielectric * (T(1) - fss - fms) * ld[ch];
      y[ch] += occlusion * dielectric * (fss * ls[ch] + fms * ld[ch]);
      // Metal layer: f0 = c, f90 = 1.
      const T mavg = c[ch] + (T(1) - c[ch]) * T(1.0 / 21.0);
      const T mss = c[ch] * scale + bias;
      const T mms = mss * mavg * ems / (T(1) - ems * mavg);
      x[ch] += occlusion * metal * scale * ls[ch];
      y[ch] += occlusion * metal * bias * ls[ch];
      m[ch] = occlusion * metal * mms * ld[ch];
    }
  }
  const V3<T> e = sp.base;  // the emission, when the lighting adds it
  const V3<T> primary{e.x + c[0] * x[0] + m[0], e.y + c[1] * x[1] + m[1], e.z + c[2] * x[2] + m[2]};
  const V3<T> rest{y[0], y[1], y[2]};
  if (sp.separate_specular) {
    if (secondary) *secondary = finish_colour(sp, rest);
    return finish_colour(sp, primary);
  }
  return finish_colour(sp, primary + rest);
}

}  // namespace facet::lighting
