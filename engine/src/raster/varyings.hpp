// Internal: the varying layout, the one place that decides which values a triangle carries from
// its vertices to its pixels and where each lives in the attribute block (ClipVertex::attr,
// ScreenTriangle::attr, the attribute planes). The frame plan decides it once per (object,
// material, pass) with plan_varyings(); clipping, triangle set-up and both rasterizers read it.
//
// Two counts: `clipped` floats go through clipping (every varying, both faces' colours included);
// after set-up has chosen the triangle's face (select_face), only the first `raster` floats are
// interpolated per pixel. Varyings used by one face only (the back colour) are placed last, so
// they fall outside `raster`. Plain data: the per-ISA raster kernels read `offset` directly and
// call none of the functions here (no inline code shared across ISA files: platform.md, trap 5).
#pragma once

#include <cstdint>

#include "geometry/clip.hpp"

namespace facet::raster {

enum class Varying : std::uint8_t {
  front_color,   // Gouraud: the lit colour of the front face (RGB)
  back_color,    // Gouraud, two-sided: the lit colour of the back face; moved to front_color by select_face
  eye_position,  // Phong: eye-space position (xyz)
  normal,        // Phong: eye-space normal (xyz), negated by select_face on back faces of a two-sided scene
  count
};
inline constexpr int kVaryingKinds = static_cast<int>(Varying::count);
// Every varying is three floats.
inline constexpr int kVaryingWidth = 3;

struct VaryingLayout {
  std::int8_t offset[kVaryingKinds] = {-1, -1, -1, -1};  // first float of each varying, -1: absent
  int clipped = 0;  // floats carried through clipping
  int raster = 0;   // floats interpolated per pixel (after select_face)

  bool has(Varying v) const { return offset[static_cast<int>(v)] >= 0; }
  int at(Varying v) const { return offset[static_cast<int>(v)]; }
};

// Where lighting is evaluated: per triangle (flat: no varying, one colour per triangle), per vertex
// (Gouraud: the front colour, and the back colour in a two-sided scene) or per pixel (Phong: eye
// position and normal).
enum class LitAt : std::uint8_t { triangle, vertex, pixel };
constexpr VaryingLayout plan_varyings(LitAt lit, bool two_sided) {
  VaryingLayout l;
  auto add = [&l](Varying v) {
    l.offset[static_cast<int>(v)] = static_cast<std::int8_t>(l.clipped);
    l.clipped += kVaryingWidth;
  };
  if (lit == LitAt::vertex) {
    add(Varying::front_color);
    l.raster = l.clipped;
    if (two_sided) add(Varying::back_color);
  } else if (lit == LitAt::pixel) {
    add(Varying::eye_position);
    add(Varying::normal);
    l.raster = l.clipped;
  }
  return l;
}
static_assert(plan_varyings(LitAt::pixel, true).clipped <= geometry::kMaxAttributes);
static_assert(plan_varyings(LitAt::vertex, true).clipped <= geometry::kMaxAttributes);

}  // namespace facet::raster
