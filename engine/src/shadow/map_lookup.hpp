// Internal: a shadow map as its lookup kernels read it (plain data, no inline code: the per-ISA
// files read it directly: the linker merges an inline function shared by files with different ISA
// flags into one copy, maybe the wider one), and the kernels' signature. The scalar twin
// (map.cpp) and the SIMD kernels (map_simd.hpp) do the same IEEE float operations in the same
// order, so their visibility is the same bits (tested on every ISA).
#pragma once

#include <cstddef>

namespace facet::shadow {

// The slope bias's tangent is capped (grazing light would push points through thin casters); one
// plain constant for the scalar twin and the SIMD kernels.
inline constexpr float kMaxSlopeTangent = 10.0f;

struct MapLookup {
  enum Kind : int { orthographic = 0, perspective = 1, cube = 2 };
  int kind = orthographic;
  int resolution = 0;  // texels a side
  int taps = 1;        // the filter's width: 1 (nearest), 2, 3 or 5
  // Faces, contiguous: face f's texel (x, y) at depth[f * resolution^2 + y * resolution + x].
  const float* depth = nullptr;
  float to_clip[6][16] = {};  // camera eye -> each face's clip space, row-major
  // One filter radius at a point in world units: reach * texel (orthographic), or
  // reach * texel_per_w * clip w (perspective and cube faces: a texel grows with depth).
  float texel = 0.0f, texel_per_w = 0.0f, reach = 1.0f;
  float bias_normal = 0.0f, bias_constant = 0.0f, bias_slope = 0.0f;
  // The light in camera eye space: its position (point, spot) or the unit direction towards it.
  int directional = 0;
  float light[3] = {};
  // Cube: the camera's eye -> world rotation (row-major), and the light in eye space, to pick
  // faces by the major axis of the way from the light in world space.
  float eye_to_world[9] = {};
};

// visible[i] for `count` points (camera eye space p and normal n, point i at px[i * stride] and
// so on): 1 lit, 0 in shadow, between on a filtered edge. Points without a direction (zero or
// non-finite normal or way to the light) and points behind a perspective face get 1.
using MapVisibilityFunction = void (*)(const MapLookup& map, std::size_t count, const float* px, const float* py,
                                       const float* pz, const float* nx, const float* ny, const float* nz,
                                       std::size_t stride, float* visible);

// The scalar twin (map.cpp).
void map_visibility_scalar(const MapLookup& map, std::size_t count, const float* px, const float* py, const float* pz,
                           const float* nx, const float* ny, const float* nz, std::size_t stride, float* visible);

}  // namespace facet::shadow
