// Internal: per-frame set-up of the lighting kernels. Everything here is computed in double from
// the scene's float data and then rounded once to the kernel's precision T.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "facet/lighting.hpp"
#include "facet/mesh.hpp"
#include "facet/scene.hpp"
#include "geometry/bounds.hpp"
#include "lighting/shade.hpp"

namespace facet::lighting {

// What an object's lighting takes per point and gives back, decided by the frame plan (see
// shade.hpp): a per-point albedo in place of the material's ambient and diffuse colours (the mesh's
// vertex colours), and the specular sum as a separate secondary colour (for textures).
struct LightingFeatures {
  bool color_material = false;
  bool separate_specular = false;
  bool occlusion = false;  // a per-point ambient occlusion multiplies every ambient term (Phong with an occlusion map)
  bool metal_rough = false;  // PBR: per-point metallic and roughness texels (Phong with a metallic-roughness map)
  bool projectors = false;  // spot lights with a projector filter their light per point (lit per pixel)
  // A lightmapped object (Instance::lightmap): the lightmap stands for the ambient and diffuse
  // light, so the lights give only their specular (LightmapMode::diffuse) or nothing (replace),
  // and the base colour is the emission alone.
  bool lightmapped = false;
  bool lightmap_replaces = false;
  // PBR materials: the prepared surroundings and DFG table (kept by the renderer); required then.
  const ImageLight* image_light = nullptr;
};

// Eye space -> the image light's frame for `env` seen through `view` (its rotation and three.js's
// reading of the picture): what PBR materials and the backdrop (Scene::background) look up.
Eigen::Matrix3d environment_frame(const EnvironmentLight& env, const Eigen::Matrix4d& view);

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

// Largest squared distance from `c` to a finite vertex among `n` from `p` (at least the true
// one: the float pass inflates its result by 1e-5), 0 when there is none.
double farthest_squared(const Vec3* p, std::size_t n, const Eigen::Vector3d& c);
// The sphere from the mesh's box and its farthest vertex from the box's centre, in eye space.
EyeSphere sphere_from_bounds(const Eigen::Vector3d& centre, double r2, const Eigen::Matrix4d& view, const Mat4& model);

// The box's centre as a float point, so that farthest_squared's float pass measures distances to
// the centre itself. The box's corners are float coordinates, so the midpoint is computed in
// float (halves first: no overflow). Rounding a double midpoint with cast<float>().cast<double>()
// did not survive GCC 12's vectoriser (the x and y pair skipped the round trip), which sent every
// object off the axes to the double loop.
inline Eigen::Vector3d float_centre(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  auto mid = [](double a, double b) { return double(0.5f * float(a) + 0.5f * float(b)); };
  return {mid(lo.x(), hi.x()), mid(lo.y(), hi.y()), mid(lo.z(), hi.z())};
}

// The bounds are found in at most kBoundsChunks chunks of at least kBoundsChunkVertices vertices
// (a split that depends on the vertex count only), each chunk on its own, then combined with min
// and max (exact in any order): the sphere is the same however the chunks are run.
inline constexpr std::size_t kBoundsChunks = 64;
inline constexpr std::size_t kBoundsChunkVertices = 16384;
inline std::size_t bounds_chunk_size(std::size_t n) {
  return std::max(kBoundsChunkVertices, (n + kBoundsChunks - 1) / kBoundsChunks);
}

// The eye-space sphere of the n points p (an object, or a part of one). run(chunks, fn) calls fn(c)
// once for every chunk c in [0, chunks), in any order and on any threads (a parallel loop), or in turn.
template <class Run>
EyeSphere eye_bounding_sphere(const Vec3* p, std::size_t n, const Eigen::Matrix4d& view, const Mat4& model, const Run& run) {
  const std::size_t size = bounds_chunk_size(n), chunks = (n + size - 1) / size;
  Eigen::Vector3d lo[kBoundsChunks], hi[kBoundsChunks];
  bool found[kBoundsChunks] = {};
  double r2[kBoundsChunks] = {};
  run(chunks, [&](std::size_t c) { found[c] = geometry::finite_box(p + c * size, std::min(size, n - c * size), lo[c], hi[c]); });
  Eigen::Vector3d box_lo = Eigen::Vector3d::Constant(HUGE_VAL), box_hi = -box_lo;
  bool any = false;
  for (std::size_t c = 0; c < chunks; ++c) {
    if (!found[c]) continue;
    any = true;
    box_lo = box_lo.cwiseMin(lo[c]), box_hi = box_hi.cwiseMax(hi[c]);
  }
  if (!any) return {Eigen::Vector3d::Zero(), 0.0};  // no finite vertex
  const Eigen::Vector3d centre = float_centre(box_lo, box_hi);
  run(chunks, [&](std::size_t c) { r2[c] = farthest_squared(p + c * size, std::min(size, n - c * size), centre); });
  double farthest = 0.0;
  for (std::size_t c = 0; c < chunks; ++c) farthest = std::max(farthest, r2[c]);
  return sphere_from_bounds(centre, farthest, view, model);
}
// A looser sphere in one pass, for a part of an object (light_instance's chunks): centred on the
// box of its finite points, with the box's half diagonal for radius. With `box` (an ISA's
// SimdKernels::box) the box of finite data is found in SIMD; the same box either way.
inline EyeSphere eye_box_sphere(const Vec3* p, std::size_t n, const Eigen::Matrix4d& view, const Mat4& model,
                                simd::BoxFunction box = nullptr) {
  Eigen::Vector3d lo, hi;
  float flo[3], fhi[3];
  if (box && n > 0 && box(p->data(), n, flo, fhi)) {
    lo = Eigen::Vector3d(flo[0], flo[1], flo[2]), hi = Eigen::Vector3d(fhi[0], fhi[1], fhi[2]);
  } else if (!geometry::finite_box(p, n, lo, hi)) {
    return {Eigen::Vector3d::Zero(), 0.0};  // no finite vertex
  }
  return sphere_from_bounds(0.5 * (lo + hi), 0.25 * (hi - lo).squaredNorm(), view, model);
}

// The runner without threads: every chunk in turn.
inline constexpr auto chunks_in_turn = [](std::size_t chunks, const auto& fn) {
  for (std::size_t c = 0; c < chunks; ++c) fn(c);
};
template <class Run>
EyeSphere eye_bounding_sphere(const Mesh& mesh, const Eigen::Matrix4d& view, const Mat4& model, const Run& run) {
  return eye_bounding_sphere(mesh.positions.data(), mesh.positions.size(), view, model, run);
}
inline EyeSphere eye_bounding_sphere(const Mesh& mesh, const Eigen::Matrix4d& view, const Mat4& model) {
  return eye_bounding_sphere(mesh, view, model, chunks_in_turn);
}

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
