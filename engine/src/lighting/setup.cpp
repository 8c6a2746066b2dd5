#include "lighting/setup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "lighting/pbr.hpp"
#include "lighting/soa.hpp"

namespace facet::lighting {
namespace {

using Vec3d = Eigen::Vector3d;

// cos of an angle in degrees, exact at 0, 90 and 180 so that cone edges at those angles are exact.
double cos_deg(double deg) {
  if (deg == 0.0) return 1.0;
  if (deg == 90.0) return 0.0;
  if (deg == 180.0) return -1.0;
  return std::cos(deg * std::numbers::pi / 180.0);
}

template <class T>
V3<T> v3(const Vec3d& v) {
  return {T(v.x()), T(v.y()), T(v.z())};
}

// A PBR material (pbr_shade.hpp): the lights carry pi d_i (the irradiance that shows a white
// Lambertian surface as d_i) and a_i; the specular colour, which the PBR kernel does not read,
// is set so large that the frame plan's cull bound never drops a lit light (only a range window's
// exact zeros drop one). The base holds the emission alone.
template <class T>
void set_pbr_terms(const Scene& scene, const Eigen::Matrix4d& view, const Material& material, LightingFeatures features,
                   ShadeParams<T>& sp) {
  PbrTerms<T>& q = sp.pbr;
  q.on = true;
  q.base_color = v3<T>(material.base_color.cast<double>());
  q.metallic = T(std::clamp(double(material.metallic), 0.0, 1.0));
  const double roughness = std::clamp(double(material.roughness), pbr::kMinRoughness<double>, 1.0);
  q.roughness = T(roughness);
  q.roughness_factor = T(std::clamp(double(material.roughness), 0.0, 1.0));
  q.alpha = T(roughness * roughness);
  pbr::Material<double> m;
  m.ior = material.ior;
  m.specular_color = {material.specular_color.x(), material.specular_color.y(), material.specular_color.z()};
  const V3<double> f0 = pbr::dielectric_f0(m);
  const double w = std::clamp(double(material.specular_weight), 0.0, 1.0);
  q.f0 = {T(f0.x * w), T(f0.y * w), T(f0.z * w)};
  q.f90 = T(w);
  // The surroundings: the environment picture when the scene has one, else its ambient as a
  // uniform radiance (never both: GL's default ambient of 0.2 is not meant as light around a model).
  q.ambient = scene.environment_light.source == EnvironmentSource::none ? v3<T>(scene.global_ambient.cast<double>()) : V3<T>{};
  q.image = features.image_light;
  const EnvironmentLight& env = scene.environment_light;
  q.intensity = T(env.intensity);
  const Eigen::Matrix3d to_env = environment_frame(env, view);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) q.to_env[3 * r + c] = T(to_env(r, c));
  sp.base = v3<T>(material.emissive.cast<double>());
  sp.emission = sp.base, sp.ambient = V3<T>{}, sp.scene_ambient = V3<T>{};
  for (EyeLight<T>& L : sp.lights) {
    const Light& light = scene.lights[static_cast<std::size_t>(L.scene_light)];
    L.ambient = v3<T>(light.ambient.cast<double>());
    L.diffuse = v3<T>(std::numbers::pi * light.diffuse.cast<double>());
    const T big = T(1e30);
    L.specular = {big, big, big};
  }
}

}  // namespace

Eigen::Matrix3d environment_frame(const EnvironmentLight& env, const Eigen::Matrix4d& view) {
  // eye -> world (the view's inverse rotation), then world -> the picture's frame: the
  // surroundings turned by rotation_deg about +Y, so a world direction is the picture's direction
  // turned back; and three.js's reading of the picture (its centre column seen along +X, u = 1/2 +
  // atan2(z, x) / 2 pi) onto the image light's (centre along -Z), a quarter turn.
  const Eigen::Matrix3d to_world = view.topLeftCorner<3, 3>().inverse();
  const double a = (90.0 - double(env.rotation_deg)) * std::numbers::pi / 180.0;
  Eigen::Matrix3d turn;
  turn << std::cos(a), 0.0, std::sin(a), 0.0, 1.0, 0.0, -std::sin(a), 0.0, std::cos(a);
  return turn * to_world;
}

template <class T>
void make_shade_params(const Scene& scene, const Eigen::Matrix4d& view, const Material& material, bool clamp,
                       ShadeParams<T>& sp, LightingFeatures features) {
  // With colour material the per-point albedo takes the place of a_m and d_m, applied after the sum.
  const Vec3d am = features.color_material ? Vec3d(Vec3d::Ones()) : Vec3d(material.ambient.cast<double>());
  const Vec3d dm = features.color_material ? Vec3d(Vec3d::Ones()) : Vec3d(material.diffuse.cast<double>());
  const Vec3d sm = material.specular.cast<double>();
  sp.lights.clear();
  sp.color_material = features.color_material;
  sp.separate_specular = features.separate_specular;
  sp.scene_ambient = v3<T>(scene.global_ambient.cast<double>());
  sp.base = features.color_material
                ? v3<T>(material.emissive.cast<double>())
                : v3<T>(material.emissive.cast<double>() + am.cwiseProduct(scene.global_ambient.cast<double>()));
  sp.occlusion = features.occlusion;
  sp.emission = v3<T>(material.emissive.cast<double>());
  sp.ambient = features.color_material ? V3<T>{} : v3<T>(am.cwiseProduct(scene.global_ambient.cast<double>()));
  if (features.lightmapped) sp.base = v3<T>(material.emissive.cast<double>()), sp.ambient = V3<T>{};
  sp.shininess = T(material.shininess);
  sp.phong_lobe = material.specular_model == SpecularModel::phong;
  sp.local_viewer = scene.viewer == ViewerMode::local;
  sp.clamp = clamp;
  const Eigen::Matrix3d rot = view.topLeftCorner<3, 3>();
  for (std::size_t index = 0; index < scene.lights.size(); ++index) {
    const Light& light = scene.lights[index];
    if (!light.enabled) continue;
    EyeLight<T> L;
    L.scene_light = static_cast<int>(index);
    L.type = light.type;
    L.ambient = v3<T>(am.cwiseProduct(light.ambient.cast<double>()));
    L.diffuse = v3<T>(dm.cwiseProduct(light.diffuse.cast<double>()));
    L.specular = v3<T>(sm.cwiseProduct(light.specular.cast<double>()));
    if (features.lightmapped) {
      L.ambient = V3<T>{}, L.diffuse = V3<T>{};
      if (features.lightmap_replaces) L.specular = V3<T>{};
    }
    const Vec3d axis = (rot * light.direction.cast<double>()).normalized();
    if (light.type == LightType::directional) {
      L.to_light = v3<T>(-axis);
    } else {
      L.position = v3<T>((view * light.position.cast<double>().homogeneous()).head<3>());
      L.k0 = T(light.constant_attenuation);
      L.k1 = T(light.linear_attenuation);
      L.k2 = T(light.quadratic_attenuation);
      L.inv_range = light.range > 0.0f ? T(1.0 / double(light.range)) : T(0);
      if (light.attenuation_model == AttenuationModel::linear_range) {
        L.linear_range = true;
        L.range_min = T(light.range_min);
        L.range_max = T(light.range_max);
        L.inv_range_max = T(1.0 / double(light.range_max));
      }
    }
    if (light.type == LightType::spot) {
      L.spot_axis = v3<T>(axis);
      L.spot_shape = light.spot_shape;
      L.has_cone = light.spot_cutoff_deg != 180.0f;
      L.cos_cutoff = T(cos_deg(light.spot_cutoff_deg));
      L.spot_exponent = T(light.spot_exponent);
      const double cos_outer = cos_deg(light.spot_outer_deg), cos_inner = cos_deg(light.spot_inner_deg);
      L.cos_outer = T(cos_outer);
      L.inv_cone_span = cos_inner > cos_outer ? T(1.0 / (cos_inner - cos_outer)) : T(0);
      L.spot_falloff = T(light.spot_falloff);
    }
    sp.lights.push_back(L);
  }
  sp.pbr = PbrTerms<T>{};
  sp.metal_rough = features.metal_rough && material.model == MaterialModel::pbr;
  if (material.model == MaterialModel::pbr) set_pbr_terms(scene, view, material, features, sp);
}

template <class T>
EyeTransform<T> make_eye_transform(const Eigen::Matrix4d& view, const Mat4& model) {
  const Eigen::Matrix4d mv = view * model.cast<double>();
  Eigen::Matrix3d nm = mv.topLeftCorner<3, 3>().inverse().transpose();
  // Normals are renormalised after this transform, so its scale is free: an object scaled by 1e6
  // gave normals of length 1e-6, whose squared length the kernels take for a zero normal (unlit).
  // A power of two brings it near 1 without changing a bit of any normal's direction; scales
  // within 2^+-8 are left as they are.
  if (const double big = nm.cwiseAbs().maxCoeff(); std::isfinite(big) && big > 0.0 && (big > 256.0 || big < 1.0 / 256.0)) {
    nm *= std::ldexp(1.0, -std::ilogb(big));
  }
  EyeTransform<T> xf{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) xf.position[4 * r + c] = T(mv(r, c));
    for (int c = 0; c < 3; ++c) xf.normal[3 * r + c] = T(nm(r, c));
  }
  return xf;
}

// Largest squared distance from `c` to a finite vertex. A float pass with packed arithmetic
// (soa.cpp) first, the scalar double loop only when it fails. Its result is
// inflated by 1e-5 relative, far above its rounding (a few float ulps on each square and sum), so
// the sphere still holds every vertex. An infinite result (a non-finite vertex, or a difference
// too large to square in float) sends the mesh to the double loop, which leaves non-finite
// vertices out by the comparison's order (NaN and Inf fail it).
double farthest_squared(const Vec3* positions, std::size_t n, const Eigen::Vector3d& c) {
  const float cf[3] = {float(c.x()), float(c.y()), float(c.z())};
  if (Eigen::Vector3d(cf[0], cf[1], cf[2]) == c) {  // so the float distances are to `c` itself
    const double r2 = farthest_squared_float(positions, n, cf);
    if (r2 <= 1e38) return r2 * (1 + 1e-5);
  }
  const double cx = c.x(), cy = c.y(), cz = c.z();
  double r2 = 0;
  for (const Vec3& p : std::span<const Vec3>(positions, n)) {
    const double dx = double(p.x()) - cx, dy = double(p.y()) - cy, dz = double(p.z()) - cz;
    const double q = dx * dx + dy * dy + dz * dz;
    r2 = q > r2 && q <= std::numeric_limits<double>::max() ? q : r2;
  }
  return r2;
}

EyeSphere sphere_from_bounds(const Eigen::Vector3d& c, double r2, const Eigen::Matrix4d& view, const Mat4& model) {
  // Radius to the farthest finite vertex, into eye space scaled by the Frobenius norm of the
  // linear part (>= its largest stretch).
  const Eigen::Matrix4d mv = view * model.cast<double>();
  return {(mv * c.homogeneous()).head<3>(), std::sqrt(r2) * mv.topLeftCorner<3, 3>().norm() * (1 + 1e-9)};
}

void lights_to_drop(const ShadeParams<double>& params, const EyeSphere& sphere, double budget,
                    std::vector<bool>& drop, std::vector<CullCandidate>& candidates) {
  using Candidate = CullCandidate;
  candidates.clear();
  drop.assign(params.lights.size(), false);
  for (std::size_t i = 0; i < params.lights.size(); ++i) {
    const EyeLight<double>& L = params.lights[i];
    if (L.type == LightType::directional) continue;
    const Eigen::Vector3d pos(L.position.x, L.position.y, L.position.z);
    const double d_min = std::max(0.0, (pos - sphere.centre).norm() - sphere.radius);
    if ((L.inv_range > 0.0 && d_min * L.inv_range >= 1.0) || (L.linear_range && d_min >= L.range_max + L.range_min)) {
      drop[i] = true;  // the light is zero at every point of the object
      continue;
    }
    const double att = L.linear_range ? std::clamp((L.range_max - d_min + L.range_min) / L.range_max, 0.0, 1.0)
                                      : 1.0 / std::max(L.k0 + L.k1 * d_min + L.k2 * d_min * d_min, 1e-6);
    const double colour = std::max({L.ambient.x + L.diffuse.x + L.specular.x, L.ambient.y + L.diffuse.y + L.specular.y,
                                    L.ambient.z + L.diffuse.z + L.specular.z});
    candidates.push_back({i, colour * att});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.bound < b.bound || (a.bound == b.bound && a.index < b.index);
  });
  double spent = 0;
  for (const Candidate& c : candidates) {
    if (spent + c.bound >= budget) break;
    spent += c.bound;
    drop[c.index] = true;
  }
}

template <class T>
std::size_t remove_lights(ShadeParams<T>& params, const std::vector<bool>& drop) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < params.lights.size(); ++i)
    if (!drop[i]) params.lights[kept++] = params.lights[i];
  const std::size_t removed = params.lights.size() - kept;
  params.lights.resize(kept);
  return removed;
}

template std::size_t remove_lights<double>(ShadeParams<double>&, const std::vector<bool>&);
template std::size_t remove_lights<float>(ShadeParams<float>&, const std::vector<bool>&);
template void make_shade_params<double>(const Scene&, const Eigen::Matrix4d&, const Material&, bool,
                                        ShadeParams<double>&, LightingFeatures);
template void make_shade_params<float>(const Scene&, const Eigen::Matrix4d&, const Material&, bool,
                                       ShadeParams<float>&, LightingFeatures);
template EyeTransform<double> make_eye_transform<double>(const Eigen::Matrix4d&, const Mat4&);
template EyeTransform<float> make_eye_transform<float>(const Eigen::Matrix4d&, const Mat4&);

}  // namespace facet::lighting
