// Internal: the camera pass's object order (TransparentOrder), one rule for draw_order and the
// renderer's frame plan.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "facet/scene.hpp"
#include "geometry/bounds.hpp"

namespace facet::scene_order {

struct ObjectKey {
  double depth = 0;  // eye-space depth of the mesh box's centre (larger is farther); transparent objects only
  std::uint32_t object = 0;
  bool transparent = false;
};

// -z in eye space of the centre of the mesh's box of finite vertices; 0 when there is none or the
// result is not finite (such an object draws nothing anyway).
inline double eye_depth(const Mesh& mesh, const Mat4& model, const Eigen::Matrix4d& view) {
  Eigen::Vector3d lo, hi;
  if (!geometry::finite_box(mesh.positions, lo, hi)) return 0.0;
  const Eigen::Vector4d c = (view * model.cast<double>()) * (0.5 * (lo + hi)).homogeneous();
  return std::isfinite(c.z()) ? -c.z() : 0.0;
}

// A total order, so std::sort (which allocates nothing) gives one result: opaque objects first in
// scene order, then transparent ones farthest first, ties in scene order.
inline bool before(const ObjectKey& a, const ObjectKey& b) {
  if (a.transparent != b.transparent) return !a.transparent;
  if (a.transparent && a.depth != b.depth) return a.depth > b.depth;
  return a.object < b.object;
}

// Every object's key in drawing order under back_to_front, seen through `view` (`keys` keeps its
// capacity). Returns false, leaving scene order, when no object is transparent.
inline bool order_objects(const Scene& scene, const Eigen::Matrix4d& view, std::vector<ObjectKey>& keys) {
  keys.resize(scene.objects.size());
  bool any = false;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const Instance& inst = scene.objects[o];
    ObjectKey& k = keys[o];
    k.object = static_cast<std::uint32_t>(o);
    k.transparent = is_transparent(scene, inst);
    k.depth = k.transparent && inst.mesh < scene.meshes.size() ? eye_depth(scene.meshes[inst.mesh].mesh, inst.model, view)
                                                               : 0.0;
    any = any || k.transparent;
  }
  if (any) std::sort(keys.begin(), keys.end(), before);
  return any;
}

}  // namespace facet::scene_order
