#include "lighting/setup.hpp"

#include <cmath>
#include <numbers>

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

}  // namespace

template <class T>
ShadeParams<T> make_shade_params(const Scene& scene, const Eigen::Matrix4d& view, const Material& material,
                                 bool clamp) {
  const Vec3d am = material.ambient.cast<double>(), dm = material.diffuse.cast<double>(),
              sm = material.specular.cast<double>();
  ShadeParams<T> sp;
  sp.base = v3<T>(material.emissive.cast<double>() + am.cwiseProduct(scene.global_ambient.cast<double>()));
  sp.shininess = T(material.shininess);
  sp.local_viewer = scene.viewer == ViewerMode::local;
  sp.clamp = clamp;
  const Eigen::Matrix3d rot = view.topLeftCorner<3, 3>();
  for (const Light& light : scene.lights) {
    if (!light.enabled) continue;
    EyeLight<T> L;
    L.type = light.type;
    L.ambient = v3<T>(am.cwiseProduct(light.ambient.cast<double>()));
    L.diffuse = v3<T>(dm.cwiseProduct(light.diffuse.cast<double>()));
    L.specular = v3<T>(sm.cwiseProduct(light.specular.cast<double>()));
    const Vec3d axis = (rot * light.direction.cast<double>()).normalized();
    if (light.type == LightType::directional) {
      L.to_light = v3<T>(-axis);
    } else {
      L.position = v3<T>((view * light.position.cast<double>().homogeneous()).head<3>());
      L.k0 = T(light.constant_attenuation);
      L.k1 = T(light.linear_attenuation);
      L.k2 = T(light.quadratic_attenuation);
      L.inv_range = light.range > 0.0f ? T(1.0 / double(light.range)) : T(0);
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
  return sp;
}

template <class T>
EyeTransform<T> make_eye_transform(const Eigen::Matrix4d& view, const Mat4& model) {
  const Eigen::Matrix4d mv = view * model.cast<double>();
  const Eigen::Matrix3d nm = mv.topLeftCorner<3, 3>().inverse().transpose();
  EyeTransform<T> xf{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) xf.position[4 * r + c] = T(mv(r, c));
    for (int c = 0; c < 3; ++c) xf.normal[3 * r + c] = T(nm(r, c));
  }
  return xf;
}

template ShadeParams<double> make_shade_params<double>(const Scene&, const Eigen::Matrix4d&, const Material&, bool);
template ShadeParams<float> make_shade_params<float>(const Scene&, const Eigen::Matrix4d&, const Material&, bool);
template EyeTransform<double> make_eye_transform<double>(const Eigen::Matrix4d&, const Mat4&);
template EyeTransform<float> make_eye_transform<float>(const Eigen::Matrix4d&, const Mat4&);

}  // namespace facet::lighting
