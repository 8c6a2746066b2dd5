// Internal: the glTF 2.0 metallic-roughness BRDF (the specification's Appendix B, with
// KHR_materials_ior and KHR_materials_specular), the reference the per-vertex and per-pixel
// kernels are measured against. Templates on the scalar type: T = double is the reference.
//
//   f = mix(dielectric, metal, metallic)
//   dielectric = (1 - F_d) c / pi + F_d D V        F_d = Schlick(f0_d w, w, v.h)
//   metal      = F_m D V                            F_m = Schlick(c, 1, v.h)
//   f0_d = min(((ior - 1) / (ior + 1))^2 specular_colour, 1),  w = specular (weight)
//   D = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2)        Trowbridge-Reitz (GGX), a = roughness^2
//   V = 0.5 / (n.l sqrt((n.v)^2 (1 - a^2) + a^2) + n.v sqrt((n.l)^2 (1 - a^2) + a^2))
//                                                   height-correlated Smith, G / (4 n.l n.v)
// c is the base colour. Directions are unit vectors from the point: n the normal, l towards the
// light, v towards the eye. Light arriving from below the surface (n.l <= 0) or seen from below
// (n.v <= 0) contributes nothing.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "lighting/shade.hpp"

namespace facet::lighting::pbr {

// The smallest perceptual roughness the BRDF uses: at 0 the GGX lobe is a delta, which a point
// light never meets (0 / 0 at n.h = 1). A choice, not the specification's.
template <class T>
inline constexpr T kMinRoughness = T(0.045);

template <class T>
struct Material {
  V3<T> base_color{T(1), T(1), T(1)};
  T metallic = T(1), roughness = T(1);
  T ior = T(1.5);
  T specular = T(1);                            // KHR_materials_specular: specularFactor
  V3<T> specular_color{T(1), T(1), T(1)};       // KHR_materials_specular: specularColorFactor
};

template <class T>
T alpha_of(T roughness) {
  const T r = std::clamp(roughness, kMinRoughness<T>, T(1));
  return r * r;
}

template <class T>
T ggx_d(T n_dot_h, T alpha) {
  const T a2 = alpha * alpha;
  const T k = n_dot_h * n_dot_h * (a2 - T(1)) + T(1);
  return a2 / (std::numbers::pi_v<T> * k * k);
}

template <class T>
T smith_v(T n_dot_l, T n_dot_v, T alpha) {
  const T a2 = alpha * alpha;
  const T gv = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (T(1) - a2) + a2);
  const T gl = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (T(1) - a2) + a2);
  const T sum = gv + gl;
  return sum > T(0) ? T(0.5) / sum : T(0);
}

template <class T>
T schlick(T f0, T f90, T v_dot_h) {
  const T x = std::clamp(T(1) - v_dot_h, T(0), T(1));
  const T x2 = x * x;
  return f0 + (f90 - f0) * (x2 * x2 * x);
}

// The dielectric reflectance at normal incidence, per channel, before the specular weight.
template <class T>
V3<T> dielectric_f0(const Material<T>& m) {
  const T r = (m.ior - T(1)) / (m.ior + T(1));
  const T f0 = r * r;
  return {std::min(f0 * m.specular_color.x, T(1)), std::min(f0 * m.specular_color.y, T(1)),
          std::min(f0 * m.specular_color.z, T(1))};
}

// f(l, v) for unit n, l and v (per channel; no cosine).
template <class T>
V3<T> brdf(const Material<T>& m, V3<T> n, V3<T> l, V3<T> v) {
  const T n_dot_l = dot(n, l), n_dot_v = dot(n, v);
  if (!(n_dot_l > T(0) && n_dot_v > T(0))) return {T(0), T(0), T(0)};
  const V3<T> h_sum = l + v;
  const T h_len = std::sqrt(dot(h_sum, h_sum));
  // l = -v cannot happen with both above the surface; h is the unit half vector.
  const V3<T> h = (T(1) / h_len) * h_sum;
  const T n_dot_h = std::clamp(dot(n, h), T(0), T(1)), v_dot_h = std::clamp(dot(v, h), T(0), T(1));
  const T alpha = alpha_of(m.roughness);
  const T dv = ggx_d(n_dot_h, alpha) * smith_v(n_dot_l, n_dot_v, alpha);
  const V3<T> f0 = dielectric_f0(m);
  const T w = m.specular, metal = std::clamp(m.metallic, T(0), T(1));
  const T c[3] = {m.base_color.x, m.base_color.y, m.base_color.z}, f0d[3] = {f0.x, f0.y, f0.z};
  T out[3];
  for (int k = 0; k < 3; ++k) {
    const T fd = schlick(f0d[k] * w, w, v_dot_h);
    const T dielectric = (T(1) - fd) * c[k] / std::numbers::pi_v<T> + fd * dv;
    const T metal_f = schlick(c[k], T(1), v_dot_h) * dv;
    out[k] = dielectric + (metal_f - dielectric) * metal;
  }
  return {out[0], out[1], out[2]};
}

// The split-sum environment terms (Karis 2013) in double: for a white furnace's specular part,
// integral of f_spec (n.l) over the light's hemisphere = f0 scale + f90 bias, with Schlick's
// Fresnel F = f0 + (f90 - f0) (1 - v.h)^5. Found by importance-sampling the GGX normals (pdf of
// l: D n.h / (4 v.h)) along a Hammersley sequence of `samples` points: deterministic.
struct Dfg {
  double scale = 0.0, bias = 0.0;
};

inline double radical_inverse(unsigned i) {
  unsigned b = i;
  b = (b << 16u) | (b >> 16u);
  b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
  b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
  b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
  b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
  return double(b) * (1.0 / 4294967296.0);
}

// Sample i of `samples` of GGX's normal distribution for alpha a, around +z: the half vector's
// local coordinates (Hammersley point (i + 1/2) / samples, radical_inverse(i)).
inline V3<double> ggx_sample(unsigned i, unsigned samples, double a) {
  const double u1 = (i + 0.5) / samples, u2 = radical_inverse(i);
  // cos^2 theta_h = (1 - u1) / (1 + (a^2 - 1) u1).
  const double cos_h = std::sqrt((1.0 - u1) / (1.0 + (a * a - 1.0) * u1));
  const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h)), phi = 2.0 * std::numbers::pi * u2;
  return {sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h};
}

inline Dfg dfg(double n_dot_v, double roughness, unsigned samples) {
  const double a = alpha_of(roughness);
  const V3<double> v{std::sqrt(std::max(0.0, 1.0 - n_dot_v * n_dot_v)), 0.0, n_dot_v};  // n = +z
  Dfg out;
  for (unsigned i = 0; i < samples; ++i) {
    const V3<double> h = ggx_sample(i, samples, a);
    const double cos_h = h.z;
    const double v_dot_h = dot(v, h);
    const V3<double> l = (2.0 * v_dot_h) * h - v;
    const double n_dot_l = l.z;
    if (n_dot_l <= 0.0 || v_dot_h <= 0.0) continue;
    // f_spec (n.l) / pdf(l) without F: V (n.l) 4 (v.h) / (n.h).
    const double weight = smith_v(n_dot_l, n_dot_v, a) * n_dot_l * 4.0 * v_dot_h / cos_h;
    const double x = 1.0 - v_dot_h, fc = x * x * x * x * x;
    out.scale += (1.0 - fc) * weight;
    out.bias += fc * weight;
  }
  out.scale /= samples, out.bias /= samples;
  return out;
}

// Schlick's Fresnel averaged over the hemisphere with the cosine: 2 integral of F(mu) mu dmu
// = f0 + (f90 - f0) / 21.
inline double average_fresnel(double f0, double f90) { return f0 + (f90 - f0) / 21.0; }

// The light a furnace of uniform radiance 1 returns from a point seen at the n.v `d` was found
// for, per channel: single-scattering
// specular (f0 scale + f90 bias) with Fdez-Aguera's (2019) multiple-scattering term, plus the
// diffuse part on what the specular layer leaves. With albedo 1 (white base, any metallic) it is
// 1: the energy the single-scattering lobe loses comes back as multiple scattering.
inline V3<double> furnace(const Material<double>& m, const Dfg& d) {
  const V3<double> f0d = dielectric_f0(m);
  const double w = m.specular, metal = std::clamp(m.metallic, 0.0, 1.0);
  const double c[3] = {m.base_color.x, m.base_color.y, m.base_color.z}, fd[3] = {f0d.x, f0d.y, f0d.z};
  double out[3];
  for (int k = 0; k < 3; ++k) {
    // The dielectric and the metal layer, each compensated, mixed by metallic as the BRDF is.
    auto layer = [&](double f0, double f90, double diffuse) {
      const double ess = d.scale + d.bias;  // directional albedo with F = 1
      const double fss_ess = f0 * d.scale + f90 * d.bias;
      const double f_avg = average_fresnel(f0, f90);
      const double ems = 1.0 - ess;
      const double fms = fss_ess * f_avg / (1.0 - ems * f_avg);
      return fss_ess + fms * ems + diffuse * (1.0 - fss_ess - fms * ems);
    };
    const double dielectric = layer(fd[k] * w, w, c[k]);
    const double metal_part = layer(c[k], 1.0, 0.0);
    out[k] = dielectric + (metal_part - dielectric) * metal;
  }
  return {out[0], out[1], out[2]};
}

// The split-sum's first factor: the environment's radiance around the reflected direction r,
// GGX-weighted for `roughness` with the normal and the eye taken along r (Karis 2013: sum of
// L(l) n.l over GGX-sampled l, divided by the sum of n.l), Hammersley-sampled, deterministic.
// The image-based lighting's prefiltered cube map is this, tabulated.
template <class Radiance>
V3<double> prefiltered(const Radiance& radiance, const V3<double>& r, double roughness, unsigned samples) {
  const double a = alpha_of(roughness);
  // A frame around r: t and b perpendicular to it.
  const V3<double> up = std::abs(r.z) < 0.999 ? V3<double>{0.0, 0.0, 1.0} : V3<double>{1.0, 0.0, 0.0};
  V3<double> t{up.y * r.z - up.z * r.y, up.z * r.x - up.x * r.z, up.x * r.y - up.y * r.x};
  t = (1.0 / std::sqrt(dot(t, t))) * t;
  const V3<double> b{r.y * t.z - r.z * t.y, r.z * t.x - r.x * t.z, r.x * t.y - r.y * t.x};
  V3<double> sum{0.0, 0.0, 0.0};
  double weight = 0.0;
  for (unsigned i = 0; i < samples; ++i) {
    const V3<double> s = ggx_sample(i, samples, a);
    const V3<double> h = s.x * t + s.y * b + s.z * r;
    const V3<double> l = (2.0 * dot(r, h)) * h - r;
    const double n_dot_l = dot(r, l);
    if (n_dot_l <= 0.0) continue;
    sum = sum + n_dot_l * radiance(l);
    weight += n_dot_l;
  }
  return (1.0 / weight) * sum;
}

// The analytic fit of the split-sum terms for Schlick's Fresnel with f90 = 1 (Karis, "Physically
// Based Shading on Mobile", 2014; three.js evaluates the same fit), against which the tabulated
// terms of dfg() are weighed: a choice for the kernels, with its error measured.
inline Dfg dfg_fit(double n_dot_v, double roughness) {
  const double c0[4] = {-1.0, -0.0275, -0.572, 0.022}, c1[4] = {1.0, 0.0425, 1.04, -0.04};
  double r[4];
  for (int k = 0; k < 4; ++k) r[k] = roughness * c0[k] + c1[k];
  const double a004 = std::min(r[0] * r[0], std::exp2(-9.28 * std::clamp(n_dot_v, 0.0, 1.0))) * r[0] + r[1];
  return {-1.04 * a004 + r[2], 1.04 * a004 + r[3]};
}

// dfg() tabulated on a size x size grid of cell centres over n.v and roughness in [0, 1], read
// bilinearly (clamped to the outer centres): what the kernels will read instead of integrating.
class DfgTable {
 public:
  DfgTable(int size, unsigned samples) : size_(size), cells_(static_cast<std::size_t>(size) * size) {
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) cells_[static_cast<std::size_t>(j) * size + i] = dfg((i + 0.5) / size, (j + 0.5) / size, samples);
    }
  }
  Dfg at(double n_dot_v, double roughness) const {
    auto coordinate = [&](double x, int& k, double& t) {
      const double c = std::clamp(x * size_ - 0.5, 0.0, double(size_ - 1));
      k = std::min(static_cast<int>(c), size_ - 2);
      t = c - k;
    };
    int i, j;
    double s, t;
    coordinate(n_dot_v, i, s);
    coordinate(roughness, j, t);
    auto cell = [&](int a, int b) { return cells_[static_cast<std::size_t>(b) * size_ + a]; };
    const Dfg c00 = cell(i, j), c10 = cell(i + 1, j), c01 = cell(i, j + 1), c11 = cell(i + 1, j + 1);
    auto mix = [&](double a, double b, double c, double d) { return (a * (1 - s) + b * s) * (1 - t) + (c * (1 - s) + d * s) * t; };
    return {mix(c00.scale, c10.scale, c01.scale, c11.scale), mix(c00.bias, c10.bias, c01.bias, c11.bias)};
  }

 private:
  int size_;
  std::vector<Dfg> cells_;
};

}  // namespace facet::lighting::pbr
