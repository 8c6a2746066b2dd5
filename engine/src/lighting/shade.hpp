// Internal: the classic lighting model for one vertex (OpenGL 2.1 §2.14.1 plus facet's extensions),
// written once and instantiated per precision: double in lighting_reference.cpp (the oracle) and
// float in lighting_scalar.cpp (the scalar baseline, built without auto-vectorisation). Plain
// scalar code on purpose: no Eigen inside the loop (Eigen would use its own SSE packets).
//
//   colour = e_m + a_m a_scene + sum_i att_i spot_i [a_m a_i + (n.VP_i)+ d_m d_i + f_i (n.h_i)+^s s_m s_i]
//
// with Phong's lobe (R_i.V)+ in place of Blinn's (n.h_i)+ when the material asks for it.
//
// Two variations, decided per object by the frame plan (ShadeParams):
//   - colour material (glColorMaterial(AMBIENT_AND_DIFFUSE)): a per-point albedo c replaces a_m and
//     d_m, so the lights carry a_i and d_i alone and
//       colour = e_m + c (a_scene + sum_i att_i spot_i [a_i + (n.VP_i)+ d_i]) + specular;
//   - separate specular (GL_SEPARATE_SPECULAR_COLOR): the specular sum goes to its own output (the
//     secondary colour, clamped on its own) instead of into the colour, so that a texture can
//     modulate the rest and the highlight is added after it;
//   - occlusion (an occlusion map, lit per pixel): a per-point factor o in [0, 1] multiplies every
//     ambient term, a_m a_scene and each light's a_m a_i (glTF: occlusion darkens indirect light),
//       colour = e_m + o a_m a_scene + sum_i att_i spot_i [o a_m a_i + diffuse + specular].
//
// Edge-case rules (public contract in facet/lighting.hpp): see light_contribution().
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "facet/light.hpp"
#include "facet/mesh.hpp"
#include "facet/types.hpp"
#include "lighting/simd_types.hpp"

namespace facet::lighting {

template <class T> V3<T> operator+(V3<T> a, V3<T> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> V3<T> operator-(V3<T> a, V3<T> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> V3<T> operator*(T s, V3<T> a) { return {s * a.x, s * a.y, s * a.z}; }
template <class T> T dot(V3<T> a, V3<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Vectors shorter than this (or non-finite) have no direction and normalise to zero.
template <class T> inline constexpr T kMinLength = T(1e-6);
// Shadowed lights at most (facet::kMaxShadowedLights): the visibility streams a point carries.
using facet::kMaxShadowedLights;
using facet::kMaxProjectors;
// Floor of the attenuation denominator, so a light at the vertex with k0 = 0 stays finite.
template <class T> inline constexpr T kMinAttenuationDenominator = T(1e-6);

template <class T>
V3<T> normalize_or_zero(V3<T> v) {
  const T len = std::sqrt(dot(v, v));
  // Written so that NaN and Inf lengths fail the test too.
  if (!(len > kMinLength<T> && len <= std::numeric_limits<T>::max())) return {T(0), T(0), T(0)};
  return (T(1) / len) * v;
}

// NaN -> 0 (the comparison order is deliberate: NaN fails `x > 0`).
template <class T> T clamp01(T x) { return x > T(0) ? (x < T(1) ? x : T(1)) : T(0); }

class ImageLight;  // image_light.hpp

// A PBR material (Material::model == pbr) under the lights and the surroundings: the glTF BRDF
// (pbr_shade.hpp) instead of the classic terms. Set up in double, rounded once to T.
template <class T>
struct PbrTerms {
  bool on = false;
  V3<T> base_color{T(1), T(1), T(1)};  // the factor (times the albedo with colour material)
  T metallic = T(0), roughness = T(1);  // roughness held in [0.045, 1] (pbr::kMinRoughness)
  T roughness_factor = T(1);            // the material's, before that hold (per-point texels multiply it)
  T alpha = T(1);                       // roughness^2
  V3<T> f0{};                           // the dielectric's reflectance at normal incidence, times f90
  T f90 = T(1);                         // KHR_materials_specular's weight
  V3<T> ambient{};                      // uniform radiance all around: the scene's ambient
  const ImageLight* image = nullptr;    // the DFG table, and the environment when it has one
  T intensity = T(1);                   // the environment's
  T to_env[9] = {T(1), T(0), T(0), T(0), T(1), T(0), T(0), T(0), T(1)};  // eye -> environment, row-major
};

template <class T>
struct ShadeParams {
  V3<T> base{};  // e_m + a_m a_scene; with colour_material: e_m
  V3<T> scene_ambient{};  // colour_material only: a_scene (the albedo multiplies it)
  bool color_material = false;      // albedo per point; lights carry a_i, d_i unmultiplied
  bool occlusion = false;           // base splits into emission + o ambient (o per point)
  V3<T> emission{}, ambient{};      // occlusion only: e_m and a_m a_scene (base = their sum)
  bool separate_specular = false;   // specular to the secondary output
  T shininess = 0;
  bool phong_lobe = false;  // SpecularModel::phong: the lobe on R.V instead of n.h
  bool local_viewer = true;
  bool clamp = true;
  std::vector<EyeLight<T>> lights;  // enabled lights only
  PbrTerms<T> pbr;  // pbr.on: a PBR material (the lights carry pi d_i as diffuse, a_i as ambient)
  bool metal_rough = false;  // pbr: per-point metallic and roughness texels multiply the factors
};

// The PBR colour at p (pbr_shade.hpp; instantiated with light_mesh and shade_points).
// `metal_rough`: with ShadeParams::metal_rough, the point's metallic and roughness texels.
template <class T>
V3<T> shade_pbr(const ShadeParams<T>& sp, V3<T> p, V3<T> n_in, V3<T> albedo, V3<T>* secondary, const float* visibility,
                T occlusion, const float* projector, const float* metal_rough);

template <class T>
T spot_factor(const EyeLight<T>& L, T cos_angle) {
  if (L.spot_shape == SpotShape::cutoff_exponent) {
    if (!L.has_cone) return T(1);
    return cos_angle >= L.cos_cutoff ? std::pow(cos_angle > T(0) ? cos_angle : T(0), L.spot_exponent) : T(0);
  }
  if (!(cos_angle >= L.cos_outer)) return T(0);
  const T t = L.inv_cone_span > T(0) ? clamp01((cos_angle - L.cos_outer) * L.inv_cone_span) : T(1);
  return std::pow(t, L.spot_falloff);
}

// Adds light L's contribution at eye-space position p with unit (or zero) normal n: all of it to
// `colour`, or with `specular` its ambient and diffuse parts to `colour` and its specular to `specular`.
// The unit vector vp from p towards light L and L's attenuation there (distance, range window,
// spot cone); false when L adds nothing at p (attenuation 0, or a non-finite distance).
template <class T>
bool light_at(const EyeLight<T>& L, V3<T> p, V3<T>& vp, T& att) {
  att = T(1);
  if (L.type == LightType::directional) {
    vp = L.to_light;
    return true;
  }
  const V3<T> diff = L.position - p;
  const T d2 = dot(diff, diff);
  const T d = std::sqrt(d2);
  if (!(d <= std::numeric_limits<T>::max())) return false;  // NaN/Inf position or distance: no contribution
  vp = d > kMinLength<T> ? (T(1) / d) * diff : V3<T>{T(0), T(0), T(0)};
  if (L.linear_range) {
    att = clamp01((L.range_max - d + L.range_min) / L.range_max);
  } else {
    const T denom = L.k0 + L.k1 * d + L.k2 * d2;
    att = T(1) / (denom > kMinAttenuationDenominator<T> ? denom : kMinAttenuationDenominator<T>);
  }
  if (L.inv_range > T(0)) {
    const T x = d * L.inv_range, x2 = x * x;
    const T w = clamp01(T(1) - x2 * x2);
    att *= w * w;
  }
  if (L.type == LightType::spot) att *= spot_factor(L, -dot(vp, L.spot_axis));
  return att != T(0);
}

// Adds light L's contribution at eye-space position p with unit (or zero) normal n: all of it to
// `colour`, or with `specular` its ambient and diffuse parts to `colour` and its specular to `specular`.
template <class T>
void light_contribution(const ShadeParams<T>& sp, const EyeLight<T>& L, V3<T> p, V3<T> n, V3<T> eye_dir,
                        V3<T>& colour, V3<T>* specular, const float* visibility = nullptr, T occlusion = T(1),
                        const float* projector = nullptr) {
  V3<T> vp;
  T att;
  if (!light_at(L, p, vp, att)) return;
  const T n_dot_l = dot(n, vp);
  V3<T> sum = sp.occlusion ? occlusion * L.ambient : L.ambient;
  if (n_dot_l > T(0)) {
    // Blinn: n.h; Phong: R.V with R = 2 (n.L) n - L the mirror direction of the light (unit when
    // n and L are), negative R.V counting as 0.
    const T cos_lobe = sp.phong_lobe ? clamp01(dot(T(2) * n_dot_l * n - vp, eye_dir))
                                     : clamp01(dot(n, normalize_or_zero(vp + eye_dir)));
    T kd = n_dot_l, ks = std::pow(cos_lobe, sp.shininess);
    if (L.shadow >= 0 && visibility) {
      const T v = T(visibility[L.shadow]);
      kd *= v, ks *= v;
    }
    V3<T> diffuse = L.diffuse, spec = L.specular;
    if (L.projector >= 0 && projector) {  // the projected picture filters the light per channel
      const float* f = projector + 3 * L.projector;
      diffuse = {T(f[0]) * diffuse.x, T(f[1]) * diffuse.y, T(f[2]) * diffuse.z};
      spec = {T(f[0]) * spec.x, T(f[1]) * spec.y, T(f[2]) * spec.z};
    }
    if (specular) {
      sum = sum + kd * diffuse;
      *specular = *specular + att * (ks * spec);
    } else {
      sum = sum + kd * diffuse + ks * spec;
    }
  }
  colour = colour + att * sum;
}

// The stored colour: clamped to [0, 1], or (HDR) kept >= 0 and finite as a float.
template <class T>
V3<T> finish_colour(const ShadeParams<T>& sp, V3<T> c) {
  if (sp.clamp) return {clamp01(c.x), clamp01(c.y), clamp01(c.z)};
  auto hdr = [](T x) { return x > T(0) ? (x < std::numeric_limits<float>::max() ? x : T(std::numeric_limits<float>::max())) : T(0); };
  return {hdr(c.x), hdr(c.y), hdr(c.z)};
}

// The colour at p with normal n_in; `albedo` is read with colour_material, `secondary` written
// with separate_specular.
// `visibility`: per shadow slot (EyeLight::shadow), this point's visibility of that light.
// `occlusion`: the point's ambient occlusion (read with ShadeParams::occlusion).
// `projector`: per projector slot (EyeLight::projector), this point's RGB filter of that light.
template <class T>
V3<T> shade_vertex(const ShadeParams<T>& sp, V3<T> p, V3<T> n_in, V3<T> albedo = {T(1), T(1), T(1)},
                   V3<T>* secondary = nullptr, const float* visibility = nullptr, T occlusion = T(1),
                   const float* projector = nullptr, const float* metal_rough = nullptr) {
  if (sp.pbr.on) return shade_pbr(sp, p, n_in, albedo, secondary, visibility, occlusion, projector, metal_rough);
  const V3<T> n = normalize_or_zero(n_in);
  const V3<T> eye_dir = sp.local_viewer ? normalize_or_zero(V3<T>{-p.x, -p.y, -p.z}) : V3<T>{T(0), T(0), T(1)};
  const V3<T> base = sp.occlusion ? sp.emission + occlusion * sp.ambient : sp.base;
  if (!sp.color_material && !sp.separate_specular) {  // the common case, in one sum
    V3<T> colour = base;
    for (const EyeLight<T>& L : sp.lights) light_contribution<T>(sp, L, p, n, eye_dir, colour, nullptr, visibility, occlusion, projector);
    return finish_colour(sp, colour);
  }
  V3<T> colour = sp.color_material ? (sp.occlusion ? occlusion * sp.scene_ambient : sp.scene_ambient) : base;
  V3<T> specular{T(0), T(0), T(0)};
  for (const EyeLight<T>& L : sp.lights) light_contribution(sp, L, p, n, eye_dir, colour, &specular, visibility, occlusion, projector);
  if (sp.color_material) colour = sp.base + V3<T>{albedo.x * colour.x, albedo.y * colour.y, albedo.z * colour.z};
  if (sp.separate_specular) {
    if (secondary) *secondary = finish_colour(sp, specular);
    return finish_colour(sp, colour);
  }
  return finish_colour(sp, colour + specular);
}

// Model -> eye transform in the kernel's precision: 3x4 affine for positions, 3x3 for normals
// (inverse transpose of the model-view's linear part), row-major.
template <class T>
struct EyeTransform {
  T position[12];
  T normal[9];
};

// Transforms and lights vertices [begin, end) of `mesh`; writes colour i to out[i] (and, with
// separate_specular, the secondary colour to secondary[i]). colour_material reads mesh.colors.
// With `index`, vertices index[begin, end) instead. `normals` (one per mesh vertex) replaces
// mesh.normals when given (per-vertex relief).
template <class T>
void light_mesh(const ShadeParams<T>& sp, const EyeTransform<T>& xf, const Mesh& mesh, bool back_side,
                std::size_t begin, std::size_t end, Color3* out, Color3* secondary,
                const std::uint32_t* index = nullptr, const Vec3* normals = nullptr) {
  if (!normals) normals = mesh.normals.data();
  const T* m = xf.position;
  const T* nm = xf.normal;
  const T sign = back_side ? T(-1) : T(1);
  for (std::size_t k = begin; k < end; ++k) {
    const std::size_t i = index ? index[k] : k;
    const T px = T(mesh.positions[i].x()), py = T(mesh.positions[i].y()), pz = T(mesh.positions[i].z());
    const T nx = sign * T(normals[i].x()), ny = sign * T(normals[i].y()), nz = sign * T(normals[i].z());
    const V3<T> p{m[0] * px + m[1] * py + m[2] * pz + m[3], m[4] * px + m[5] * py + m[6] * pz + m[7],
                  m[8] * px + m[9] * py + m[10] * pz + m[11]};
    const V3<T> n{nm[0] * nx + nm[1] * ny + nm[2] * nz, nm[3] * nx + nm[4] * ny + nm[5] * nz,
                  nm[6] * nx + nm[7] * ny + nm[8] * nz};
    V3<T> albedo{T(1), T(1), T(1)}, spec{};
    if (sp.color_material) albedo = {T(mesh.colors[i].x()), T(mesh.colors[i].y()), T(mesh.colors[i].z())};
    const V3<T> c = shade_vertex(sp, p, n, albedo, &spec);
    out[i] = Color3(float(c.x), float(c.y), float(c.z));
    if (sp.separate_specular) secondary[i] = Color3(float(spec.x), float(spec.y), float(spec.z));
  }
}

// Lights `count` points given in eye space (positions and normals, normals need not be unit):
// the per-pixel (Phong) and per-centroid (flat) entry to the same kernel. `albedo` is read with
// colour_material, `secondary` written with separate_specular. `visibility` (with shadowed
// lights): point i's visibility of the light in shadow slot k is visibility[k * count + i].
// `occlusion` (with ShadeParams::occlusion): each point's ambient occlusion. `projector` (with
// projector slots): channel c of point i's filter of slot k at projector[(3 k + c) * count + i].
// `metal_rough` (with ShadeParams::metal_rough): point i's metallic texel at [i], roughness at
// [count + i].
template <class T>
void shade_points(const ShadeParams<T>& sp, std::size_t count, const Vec3* p_eye, const Vec3* n_eye,
                  const Color3* albedo, Color3* out, Color3* secondary, const float* visibility = nullptr,
                  int shadow_slots = 0, const float* occlusion = nullptr, const float* projector = nullptr,
                  int projector_slots = 0, const float* metal_rough = nullptr) {
  for (std::size_t i = 0; i < count; ++i) {
    float vis[kMaxShadowedLights];
    for (int k = 0; k < shadow_slots; ++k) vis[k] = visibility[static_cast<std::size_t>(k) * count + i];
    const V3<T> p{T(p_eye[i].x()), T(p_eye[i].y()), T(p_eye[i].z())};
    const V3<T> n{T(n_eye[i].x()), T(n_eye[i].y()), T(n_eye[i].z())};
    V3<T> a{T(1), T(1), T(1)}, spec{};
    if (sp.color_material) a = {T(albedo[i].x()), T(albedo[i].y()), T(albedo[i].z())};
    const T o = occlusion ? T(occlusion[i]) : T(1);
    float filter[3 * kMaxProjectors];
    for (int k = 0; k < 3 * projector_slots; ++k) filter[k] = projector[static_cast<std::size_t>(k) * count + i];
    const float mr[2] = {metal_rough ? metal_rough[i] : 1.0f, metal_rough ? metal_rough[count + i] : 1.0f};
    const V3<T> c = shade_vertex(sp, p, n, a, &spec, shadow_slots > 0 ? vis : nullptr, o, projector_slots > 0 ? filter : nullptr,
                                 metal_rough ? mr : nullptr);
    out[i] = Color3(float(c.x), float(c.y), float(c.z));
    if (sp.separate_specular) secondary[i] = Color3(float(spec.x), float(spec.y), float(spec.z));
  }
}

// Each precision is instantiated in exactly one file, with that file's compile flags.
extern template V3<double> shade_pbr<double>(const ShadeParams<double>&, V3<double>, V3<double>, V3<double>, V3<double>*,
                                             const float*, double, const float*, const float*);
extern template V3<float> shade_pbr<float>(const ShadeParams<float>&, V3<float>, V3<float>, V3<float>, V3<float>*,
                                           const float*, float, const float*, const float*);
extern template void light_mesh<double>(const ShadeParams<double>&, const EyeTransform<double>&, const Mesh&, bool,
                                        std::size_t, std::size_t, Color3*, Color3*, const std::uint32_t*, const Vec3*);
extern template void light_mesh<float>(const ShadeParams<float>&, const EyeTransform<float>&, const Mesh&, bool,
                                       std::size_t, std::size_t, Color3*, Color3*, const std::uint32_t*, const Vec3*);
extern template void shade_points<double>(const ShadeParams<double>&, std::size_t, const Vec3*, const Vec3*,
                                          const Color3*, Color3*, Color3*, const float*, int, const float*, const float*, int,
                                          const float*);
extern template void shade_points<float>(const ShadeParams<float>&, std::size_t, const Vec3*, const Vec3*,
                                         const Color3*, Color3*, Color3*, const float*, int, const float*, const float*, int,
                                         const float*);

}  // namespace facet::lighting
