// Internal: shadow maps (shadow buffers). A light's map is one depth image per face, rendered
// from the light by depth-only passes of the renderer's own tile pipeline (frame/pass.hpp), and
// a lookup that decides a shaded point's visibility of the light from it:
//   - a directional light: one orthographic face looking along the light, fitted to the box of
//     the casters' bounds in light space, cut to the light-space footprint of the camera's
//     frustum (a caster outside that footprint cannot shade a visible point; casters behind the
//     camera still cast);
//   - a spot light: one perspective face from the light along its axis, its field of view the
//     outer cone (plus the filter's margin); cones wider than 75 degrees use a cube;
//   - a point light: a cube of six perspective faces (omni), each a little wider than 90 degrees
//     so that a filter's footprint never leaves its face (no seams at face borders).
// Depth range: from the casters' bounds (near at least far / 1000). A point's depth is compared
// with the stored depth after the point moves towards the light and along its normal by the
// light's ShadowBias, in filter radii at the point (facet/light.hpp); a filter of N x N texels (N = 2, 3, 5)
// averages (N - 1)^2 bilinear 2x2 comparisons (GL's LINEAR depth compare), so visibility varies
// smoothly as the point moves. Texels outside the map count as lit: the fit keeps every caster
// that matters inside it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "facet/image.hpp"
#include "facet/light.hpp"
#include "shadow/map_lookup.hpp"
#include "shadow/target.hpp"

namespace facet::shadow {

// World-space boxes of the casters of a frame (objects with cast_shadows), one per object with a
// finite vertex: what the maps are fitted to.
struct CasterBounds {
  std::vector<Eigen::Vector3d> lo, hi;
  bool empty() const { return lo.empty(); }
};

class ShadowMap {
 public:
  // Plans the map of `light` (enabled, shadow.method == map) for a frame: its faces' views and
  // projections fitted to `casters` and the camera (`camera_view`: world -> eye,
  // `camera_projection`), and their depth images (resolution^2 floats each, allocated here).
  // After plan(), empty() when no caster can shade a visible point: no pass runs and every point
  // is lit.
  void plan(const Light& light, const CasterBounds& casters, const Eigen::Matrix4d& camera_view,
            const Eigen::Matrix4d& camera_projection);
  bool empty() const { return faces_ == 0; }
  int kind() const { return lookup_.kind; }  // MapLookup::Kind (valid when not empty())
  int resolution() const { return resolution_; }
  int face_count() const { return faces_; }
  const Eigen::Matrix4d& face_view(int f) const { return face_[f].view; }              // world -> light eye
  const Eigen::Matrix4d& face_projection(int f) const { return face_[f].projection; }  // light eye -> clip
  // The face's depth image as the depth-only pass writes it (window depth in [0, 1], y down).
  DepthView depth_view(int f);
  // Per tile of `tile_size` pixels of face f: 1 when it may hold anything but far depth. The
  // depth images persist from frame to frame; a new size marks every tile.
  std::uint8_t* dirty_tiles(int f, int tile_size);
  // The lookup kernel: an ISA's (the simd path), or null for the scalar twin.
  void set_kernel(MapVisibilityFunction kernel) { kernel_ = kernel; }
  // Bytes a map of `light` takes (its faces' depth images).
  static std::size_t bytes(const Light& light);

  // visible[i] in [0, 1]: how much of the filter's footprint around point i (camera eye space p,
  // normal n, coordinates px[i * stride] and so on) sees the light (map_lookup.hpp).
  void visibility(std::size_t count, const float* px, const float* py, const float* pz, const float* nx,
                  const float* ny, const float* nz, std::size_t stride, float* visible) const;

 private:
  struct Face {
    Eigen::Matrix4d view = Eigen::Matrix4d::Identity(), projection = Eigen::Matrix4d::Identity();
  };
  int faces_ = 0, resolution_ = 0;
  Face face_[6];
  std::vector<float> depth_;  // the faces' depth images, one after another
  std::vector<std::uint8_t> dirty_;  // per face and tile (dirty_tile_size_ pixels a side)
  int dirty_tile_size_ = 0;
  MapLookup lookup_;
  MapVisibilityFunction kernel_ = nullptr;
};

}  // namespace facet::shadow
