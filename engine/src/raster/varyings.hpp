// Internal: the varying layout, the one place that decides which values a triangle carries from
// its vertices to its pixels and where each lives in the attribute block (ClipVertex::attr,
// ScreenTriangle::attr, the attribute planes). The frame plan decides it once per (object,
// material, pass) with plan_varyings(); clipping, triangle set-up and both rasterizers read it.
//
// Two counts: `clipped` floats go through clipping (every varying, both faces' colours included);
// after set-up has chosen the triangle's face (select_face), only the first `raster` floats are
// interpolated per pixel. Varyings used by one face only (the back colour) are placed last, so
// they fall outside `raster`. Plain data: the per-ISA raster kernels read `offset` directly and
// call none of the functions here (no inline code shared across ISA files: the linker merges an
// inline function compiled with different ISA flags, and the wider copy may run on a CPU without it).
#pragma once

#include <array>
#include <cstdint>

#include "geometry/clip.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::raster {

enum class Varying : std::uint8_t {
  front_color,      // Gouraud: the lit colour of the front face (RGB; the primary colour with a texture)
  front_secondary,  // Gouraud with separate specular: the front face's specular (RGB)
  eye_position,     // Phong: eye-space position (xyz)
  normal,           // Phong: eye-space normal (xyz), negated by select_face on back faces of a two-sided scene
  albedo,           // Phong with vertex colours: the colour-material albedo (RGB)
  uv,               // textured: the mesh's texture coordinates (the pixel program applies uv_scale)
  environment,      // flat and Gouraud with an environment map: the vertices' texgen coordinates (xyz)
  back_color,       // Gouraud, two-sided: the back face's colour; moved to front_color by select_face
  back_secondary,   // Gouraud, two-sided, separate specular: moved to front_secondary by select_face
  tangent,          // Phong with a normal map: eye-space tangent (xyz), negated by select_face with the normal
  tangent_sign,     // Phong with a normal map: the bitangent's sign w per vertex; set-up makes it the
                    // triangle's (ScreenTriangle::bitangent_negative), never interpolated
  lightmap_uv,      // a lightmapped object: the mesh's lightmap coordinates (Mesh::lightmap_uvs)
  count
};
inline constexpr int kVaryingKinds = static_cast<int>(Varying::count);
// Floats per varying: colours, positions and normals three, texture coordinates two.
inline constexpr int kVaryingWidth[kVaryingKinds] = {3, 3, 3, 3, 3, 2, 3, 3, 3, 3, 1, 2};
constexpr int width_of(Varying v) { return kVaryingWidth[static_cast<int>(v)]; }

// The varyings the pixel stages generate at the vertices from the eye-space position and normal
// (pixel/stages.hpp: generate_at_vertex; the object set-up fills them, in this order).
inline constexpr std::array<Varying, 1> kGeneratedVaryings = {Varying::environment};

struct VaryingLayout {
  std::int8_t offset[kVaryingKinds] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};  // first float of each varying, -1: absent
  int clipped = 0;  // floats carried through clipping
  int raster = 0;   // floats interpolated per pixel (after select_face)

  constexpr bool has(Varying v) const { return offset[static_cast<int>(v)] >= 0; }
  constexpr int at(Varying v) const { return offset[static_cast<int>(v)]; }
};

// Where lighting is evaluated: per triangle (flat: no varying, one colour per triangle), per vertex
// (Gouraud: the front colour, and the back colour in a two-sided scene) or per pixel (Phong: eye
// position and normal).
enum class LitAt : std::uint8_t { triangle, vertex, pixel };

// What a draw's material and mesh add to the lighting's varyings.
struct SurfaceNeeds {
  bool secondary = false;  // separate specular (a texture modulates the primary colour only)
  bool albedo = false;     // vertex colours, lit per pixel
  bool uv = false;         // a texture
  bool environment = false;  // an environment map generated at the vertices (flat, Gouraud)
  bool tangent = false;      // a normal map, lit per pixel
  bool lightmap = false;     // baked light (never with vertex colours, environment, normal or bump maps)
};

constexpr VaryingLayout plan_varyings(LitAt lit, bool two_sided, SurfaceNeeds needs = {}) {
  VaryingLayout l;
  auto add = [&l](Varying v) {
    l.offset[static_cast<int>(v)] = static_cast<std::int8_t>(l.clipped);
    l.clipped += width_of(v);
  };
  if (lit == LitAt::vertex) {
    add(Varying::front_color);
    if (needs.secondary) add(Varying::front_secondary);
  } else if (lit == LitAt::pixel) {
    add(Varying::eye_position);
    add(Varying::normal);
    if (needs.albedo) add(Varying::albedo);
  }
  if (needs.uv) add(Varying::uv);
  if (needs.lightmap) add(Varying::lightmap_uv);
  if (needs.environment && lit != LitAt::pixel) add(Varying::environment);
  const bool tangent = needs.tangent && lit == LitAt::pixel;
  if (tangent) add(Varying::tangent);
  l.raster = l.clipped;
  if (tangent) add(Varying::tangent_sign);  // read by set-up only: after `raster`
  if (lit == LitAt::vertex && two_sided) {  // one face's values only: after `raster`
    add(Varying::back_color);
    if (needs.secondary) add(Varying::back_secondary);
  }
  return l;
}
// Every per-pixel combination fits, but a normal map with vertex colours (the frame plan leaves the
// normal map out there: docs/relief.md).
static_assert(plan_varyings(LitAt::pixel, true, {true, true, true, true, true}).clipped <= geometry::kMaxAttributes);
static_assert(plan_varyings(LitAt::pixel, true, {true, true, true, true}).raster <= kMaxRasterAttributes);
static_assert(plan_varyings(LitAt::pixel, true, {true, false, true, true, true}).raster <= kMaxRasterAttributes);
static_assert(plan_varyings(LitAt::vertex, true, {true, true, true, true}).raster <= kMaxRasterAttributes);
static_assert(plan_varyings(LitAt::vertex, true, {true, true, true, true}).clipped <= geometry::kMaxAttributes);
// A lightmap: with a texture and separate specular, not with vertex colours, environment, normal
// or bump maps (scene validation refuses those).
static_assert(plan_varyings(LitAt::vertex, true, {true, false, true, false, false, true}).raster <= kMaxRasterAttributes);
static_assert(plan_varyings(LitAt::vertex, true, {true, false, true, false, false, true}).clipped <= geometry::kMaxAttributes);
static_assert(plan_varyings(LitAt::pixel, true, {true, false, true, false, false, true}).raster <= kMaxRasterAttributes);

}  // namespace facet::raster
