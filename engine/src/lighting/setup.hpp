// Internal: per-frame set-up of the lighting kernels. Everything here is computed in double from
// the scene's float data and then rounded once to the kernel's precision T.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "facet/lighting.hpp"
#include "facet/scene.hpp"
#include "facet/mesh.hpp"
#include "lighting/shade.hpp"

namespace facet::lighting {

// What an object's lighting takes per point and gives back, decided by the frame plan (see
// shade.hpp): a per-point albedo in place of the material's ambient and diffuse colours (the mesh's
// vertex colours), and the specular sum as a separate secondary colour (for textures).
struct LightingFeatures {
  bool color_material = false;
  bool separate_specular = false;
  bool occlusion = false;  // a per-point ambient occlusion multiplies every ambient term (Phong with an occlusion map)
  bool projectors = false;  // spot lights with a projector filter their light per point (lit per pixel)
};

// Fills `out` (its light list keeps its capacity, so a steady frame allocates nothing).
template <class T>
void make_shade_params(const Scene& scene, const Eigen::Matrix4d& view, const Material& material, bool clamp,
                       ShadeParams<T>& out, LightingFeatures features = {});
template <class T>
ShadeParams<T> make_shade_params(const Scene& scene, const Eigen::Matrix4d& view, const Material& material,
                                 bool clamp, LightingFeatures features = {}) {
  ShadeParams<T> out;
  make_shade_params(scene, view, material, clamp, out, features);
  return out;
}

template <class T>
EyeTransform<T> make_eye_transform(const Eigen::Matrix4d& view, const Mat4& model);

// An object's bounds in eye space: every vertex lies within `radius` of `centre`.
struct EyeSphere {
  Eigen::Vector3d centre;
  double radius;
};
EyeSphere eye_bounding_sphere(const Mesh& mesh, const Eigen::Matrix4d& view, const Mat4& model);

// Model-space box of the mesh's finite vertices, or false when it has none.
bool finite_box(const std::vector<Vec3>& positions, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

// The frame plan's light culling for one object, decided once (in double) for every path: marks
// the point and spot lights that cannot reach the sphere (range window: exactly zero there) and
// then, smallest bound first, lights whose largest possible contribution there is so small that
// all marked ones together stay below `budget` per channel:
//   contribution <= att(d_min) * max_channel(a_m a_i + d_m d_i + s_m s_i)
// since n.l, spot factors and pow are <= 1, with d_min the sphere's closest approach.
struct CullCandidate {
  std::size_t index;
  double bound;  // largest contribution on the sphere, per channel
};
// Writes the decision to `drop` (one per light); `scratch` is working memory. Both keep capacity.
void lights_to_drop(const ShadeParams<double>& params, const EyeSphere& sphere, double budget,
                    std::vector<bool>& drop, std::vector<CullCandidate>& scratch);

// Removes the marked lights (same order as params.lights); returns how many.
template <class T>
std::size_t remove_lights(ShadeParams<T>& params, const std::vector<bool>& drop);

// Half a step of 8-bit output: what the frame plan allows the removed lights to add up to.
inline constexpr double kLightCullBudget = 0.5 / 255.0;

}  // namespace facet::lighting
