// Internal: triangle assembly, the geometry stage between a pass's vertices and its bins. For one
// set-up range of an object: drop non-finite and out-of-frustum triangles, clip the ones that cross
// the near or far plane or the guard band, place the rest on screen (orientation, culling, bounds),
// attach their varyings as the pass's VaryingLayout says, set up their planes and bin them.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "facet/mesh.hpp"
#include "facet/render.hpp"
#include "geometry/clip.hpp"
#include "geometry/project.hpp"
#include "raster/bins.hpp"
#include "raster/place.hpp"
#include "raster/triangle_setup.hpp"
#include "raster/varyings.hpp"

namespace facet::raster {

// What a pass fixes for every triangle it assembles.
struct AssemblyFrame {
  geometry::Viewport viewport;
  geometry::ClipPlanes planes{};
  CullMode cull = CullMode::back;
  bool two_sided = false;
  BinGrid grid;
  // The ISA's placing kernel (the simd path), or null: the scalar twin places every triangle.
  // Records the kernel places carry no z and 1/w (ScreenTriangle::z, inv_w; set-up keeps them in
  // PendingTriangles::depth for the planes): only the scalar rasterizer reads them, and it runs
  // exactly where no kernel was given (the renderer takes both from the one ISA choice).
  simd::PlaceFunction place = nullptr;
};

enum class Placement { placed, degenerate, culled, no_pixel };

// With the screen positions (x, y, z, 1/w) of `t` set: decides whether it is drawn (non-zero area,
// not culled, some pixel centre of the viewport in its bounds), marks it back-facing or not and
// orients it clockwise on screen (`swapped`: vertices 1 and 2 were exchanged with their z and 1/w;
// the caller orders the attributes likewise), and sets its coverage data (finish_setup).
// Counter-clockwise in GL's y-up window is front-facing; a mirrored object's front faces wind the
// other way. Culling uses CullMode; a two-sided scene culls no back face.
Placement place_triangle(ScreenTriangle& t, CullMode cull, bool two_sided, bool mirrored,
                         const geometry::Viewport& viewport, bool& swapped);
// The rest of place_triangle for a triangle already oriented (`area2` = signed_area2(t) != 0,
// t.back_facing() set, not culled): placed or no_pixel.
Placement place_oriented(ScreenTriangle& t, std::int64_t area2, const geometry::Viewport& viewport, bool& swapped);
// The orientation step of place_triangle alone, from a snapped triangle's signed_area2:
// degenerate, culled, or placed (not yet known to cover a pixel) with `back_facing` set.
// Counter-clockwise in GL's y-up window is negative area in this y-down screen; a mirrored
// object's front faces wind clockwise.
inline bool is_back_facing(std::int64_t area2, bool mirrored) { return (area2 > 0) != mirrored; }
// Culling uses CullMode; a two-sided scene culls no back face.
inline bool is_culled(CullMode cull, bool two_sided, bool back_facing) {
  return (cull == CullMode::back && back_facing && !two_sided) || (cull == CullMode::front && !back_facing);
}
inline Placement orient(std::int64_t area2, CullMode cull, bool two_sided, bool mirrored, bool& back_facing) {
  if (area2 == 0) return Placement::degenerate;
  back_facing = is_back_facing(area2, mirrored);
  return is_culled(cull, two_sided, back_facing) ? Placement::culled : Placement::placed;
}

// One object's vertices as the pass sees them.
struct ObjectVertices {
  VaryingLayout layout;                               // the draw's varyings (plan_varyings)
  std::span<const std::array<float, 4>> clip;         // clip-space positions
  std::span<const geometry::ScreenVertex> screen;     // transform_vertices()
  const float* varying[kVaryingKinds] = {};           // per varying of the layout: width_of(v) floats per vertex
  const Color3* flat_front = nullptr;                 // flat shading: a colour per triangle
  const Color3* flat_back = nullptr;                  //   and its back face's in a two-sided scene
  const Color3* flat_secondary_front = nullptr;       // flat, textured: the specular per triangle
  const Color3* flat_secondary_back = nullptr;
  bool mirrored = false;                              // the model matrix has a negative determinant
  bool two_sided = false;                             // both faces drawn and lit (AssemblyFrame::two_sided or the object's own)
  // A double-sided blended object is drawn as two draws, its back faces first (frame::FaceDraw):
  // 0 both faces, 1 its front faces only, 2 its back faces only (lit as back faces).
  std::uint8_t only = 0;
  std::uint32_t object = 0;
  float alpha = 1.0f;
};

// Triangle assembly in two phases, so that only the vertices (flat: the triangles) that are
// drawn need lighting: place_range() makes the records of the range's triangles that can be
// drawn, without their varyings (no varying is read), lists them and the triangles to clip in
// `pending`, and marks their vertices in `drawn` when it is not null (relaxed atomic stores of 1:
// ranges run in parallel; flat shading lights the listed triangles instead); finish_range(), once
// those vertices are lit, attaches the varyings, sets up the planes and bins them (index =
// position in `out`), and clips the others, in triangle order, so bins list triangles in
// submission order (the clipped pieces' records follow the placed triangles' in `out`, which
// changes no bin's order). Counters go to `binning`; place_range clears `out` and `binning`.
struct PendingTriangles {
  enum Kind : std::uint8_t { placed, placed_swapped, clip };
  std::vector<std::uint32_t> triangle;  // mesh triangle numbers, in order
  std::vector<Kind> kind;
  std::vector<std::array<float, 6>> depth;  // placed triangles' oriented z and 1/w (zeros for clip)
};
void place_range(const AssemblyFrame& frame, const Mesh& mesh, const ObjectVertices& object, std::size_t begin,
                 std::size_t end, std::vector<ScreenTriangle>& out, RangeBinning& binning, PendingTriangles& pending,
                 std::uint8_t* drawn);
void finish_range(const AssemblyFrame& frame, const Mesh& mesh, const ObjectVertices& object,
                  std::vector<ScreenTriangle>& out, RangeBinning& binning, const PendingTriangles& pending);
// Both phases at once, for draws whose lighting does not depend on what is drawn (Phong lights
// pixels; RenderOptions::light_every_vertex).
void assemble_range(const AssemblyFrame& frame, const Mesh& mesh, const ObjectVertices& object, std::size_t begin,
                    std::size_t end, std::vector<ScreenTriangle>& out, RangeBinning& binning, PendingTriangles& pending);

}  // namespace facet::raster
