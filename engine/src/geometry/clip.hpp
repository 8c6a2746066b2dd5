// Internal: homogeneous clipping. A triangle in clip space is clipped against the near and far
// planes and against a guard band in x and y (so that snapped screen coordinates always fit the
// fixed-point range), by Sutherland-Hodgman, interpolating every attribute linearly in clip space
// (which is affine in model space, so correct before the perspective divide).
//
// Watertightness: an edge shared by two triangles is cut at bit-identical points in both, because
// the intersection is always computed from the endpoint inside the plane towards the one outside.
#pragma once

#include <array>
#include <cstdint>

namespace facet::geometry {

// Floats a vertex carries through clipping at most: room for any draw's varyings (the largest
// layout, raster/varyings.hpp, a two-sided Gouraud draw with a texture, separate specular and an
// environment map, carries 17; varyings.hpp asserts every layout fits), with room for the stages
// to come, so that a stage's varyings do not reach into clipping.
inline constexpr int kMaxAttributes = 24;

struct ClipVertex {
  float x, y, z, w;
  float attr[kMaxAttributes];
};

// A convex polygon gains at most one vertex per plane: 3 + 6 = 9. Rounding can make a sliver
// slightly non-convex, so the buffers have room to spare and a clip that would overflow them
// drops the triangle instead.
inline constexpr int kMaxClippedVertices = 16;

struct ClipPlanes {
  float guard_x;  // |x| <= guard_x * w keeps screen x inside the guard band
  float guard_y;
};

// Bit k set: the vertex is outside clip plane k (0 near, 1 far, 2..5 guard band -x +x -y +y).
inline std::uint32_t clip_outcode(float x, float y, float z, float w, const ClipPlanes& p) noexcept {
  return (w + z < 0.0f ? 1u : 0u) | (w - z < 0.0f ? 2u : 0u) | (p.guard_x * w + x < 0.0f ? 4u : 0u) |
         (p.guard_x * w - x < 0.0f ? 8u : 0u) | (p.guard_y * w + y < 0.0f ? 16u : 0u) |
         (p.guard_y * w - y < 0.0f ? 32u : 0u);
}
inline std::uint32_t clip_outcode(const ClipVertex& v, const ClipPlanes& planes) noexcept {
  return clip_outcode(v.x, v.y, v.z, v.w, planes);
}
// Bit k set: outside frustum plane k (0 near, 1 far, 2..5 viewport -x +x -y +y). A triangle whose
// three vertices share a bit is entirely outside.
inline std::uint32_t frustum_outcode(float x, float y, float z, float w) noexcept {
  return (w + z < 0.0f ? 1u : 0u) | (w - z < 0.0f ? 2u : 0u) | (w + x < 0.0f ? 4u : 0u) | (w - x < 0.0f ? 8u : 0u) |
         (w + y < 0.0f ? 16u : 0u) | (w - y < 0.0f ? 32u : 0u);
}
inline std::uint32_t frustum_outcode(const ClipVertex& v) noexcept { return frustum_outcode(v.x, v.y, v.z, v.w); }

// Clips triangle (a, b, c) against the planes in `outcode_union`; writes the polygon (a fan) to
// `out` and returns its vertex count (0 if nothing is left). `attribute_count` attributes are
// interpolated.
int clip_triangle(const ClipVertex& a, const ClipVertex& b, const ClipVertex& c, std::uint32_t outcode_union,
                  const ClipPlanes& planes, int attribute_count, ClipVertex* out) noexcept;

}  // namespace facet::geometry
