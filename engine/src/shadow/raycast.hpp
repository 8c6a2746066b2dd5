// Internal: ray-cast shadows. The shadow casters of a frame (objects with cast_shadows) as one
// Intel Embree scene in world space, in robust (watertight) mode, kept from frame to frame while
// the casters do not change (the camera may move), and visibility queries against it:
// a shaded point sees a light when no caster triangle lies on the segment from the point (moved
// off its surface along its normal, ShadowBias::normal) to the light, or along the ray towards a
// directional light. Whether a segment is blocked is a property of the geometry alone (robust
// traversal and a watertight triangle test), not of the BVH Embree happened to build or of the
// threads it used, so images stay byte-identical for any thread count (tested).
//
// No global state: each RayCaster owns its Embree device. Embree's builder runs on oneTBB in the
// calling thread's arena (the renderer calls build() inside its own arena, so a frame never uses
// more threads than RenderOptions::threads); the device is created without a "threads" setting,
// which would change TBB's process-wide parallelism.
#pragma once

#include <cstddef>
#include <cstdint>
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "facet/scene.hpp"
#include "facet/status.hpp"
#include "shadow/target.hpp"

namespace facet::shadow {

class RayCaster {
 public:
  RayCaster() = default;
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // The casters of `scene` for queries in the eye space of `view` (world -> eye). Objects whose
  // cast_shadows is false are left out; triangles with non-finite vertices are ignored by Embree.
  // The hierarchy is rebuilt only when the casters changed since the last build: their number,
  // their world-space vertices (model matrix times position, compared bit for bit) or their
  // triangles; reused() says whether it was kept. Errors (out of memory included) come back as a
  // Status; nothing is printed.
  Status build(const Scene& scene, const Eigen::Matrix4d& view);
  bool reused() const noexcept { return reused_; }
  bool empty() const noexcept { return triangles_ == 0; }
  std::size_t triangle_count() const noexcept { return triangles_; }
  // Radius of a sphere around the casters' vertices within +-1e18 (world space): the unit of
  // ShadowBias::normal.
  float radius() const noexcept { return radius_; }

  using Target = LightTarget;
  // visible[i] = 1 if point i (eye space p, normal n, moved by `offset` times the unit normal)
  // sees the target, else 0. Points the light clearly cannot light (may_be_lit) get 1 without a
  // ray: their diffuse and specular terms are zero whatever their visibility. Point i's
  // coordinates are px[i * stride] (likewise the others): stride 1 for structure-of-arrays
  // streams, 3 for xyz triples.
  void visibility(const Target& target, float offset, std::size_t count, const float* px, const float* py,
                  const float* pz, const float* nx, const float* ny, const float* nz, std::size_t stride,
                  float* visible) const;

 private:
  void release() noexcept;
  void release_scene() noexcept;
  // Whether the casters of `scene` are exactly the ones the current hierarchy holds.
  bool same_casters(const Scene& scene) const;
  void* device_ = nullptr;  // RTCDevice
  void* scene_ = nullptr;   // RTCScene
  std::vector<void*> geometries_;  // RTCGeometry, retained: one per caster object, in object order
  std::vector<std::array<std::size_t, 2>> counts_;  // per geometry: vertices, triangles
  float to_world_[12] = {};         // eye -> world, rows of a 3 x 4 matrix
  bool built_ = false;              // the hierarchy is complete (the last build succeeded)
  bool reused_ = false;
  std::size_t triangles_ = 0;
  float radius_ = 0.0f;
  std::string error_;  // the device's last error message (set by its error callback)
  int error_code_ = 0;
  friend void record_error(void*, int, const char*);
};

}  // namespace facet::shadow
