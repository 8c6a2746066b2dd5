// Internal: screen-space triangles. Vertices are snapped to 24.8 fixed point (8 sub-pixel bits)
// in a y-down screen (row 0 at the top; y_up images are flipped only when resolved). Coverage is
// decided by exact integer edge functions:
//
//   E_k(p) = (b.x - a.x)(p.y - a.y) - (b.y - a.y)(p.x - a.x)   for edge k = (a -> b) opposite vertex k
//
// Triangles are stored oriented so that area2 = E_0(v0) > 0 (clockwise as seen on screen); a pixel
// centre is inside when every E_k > 0, or E_k == 0 on a top or left edge (the top-left rule, as in
// Direct3D): a top edge is horizontal with the interior below it (d.y == 0, d.x > 0), a left edge
// goes up the screen (d.y < 0). Folding that into a bias, inside <=> E_k + bias_k >= 0 for all k.
//
// Ranges: |x|, |y| <= 32768 px (the guard band) -> |fixed| <= 2^23; edge deltas < 2^24; every
// product and sum below stays under 2^50, well inside int64.
#pragma once

#include <cstdint>
#include <cstring>

#include "geometry/clip.hpp"
#include "geometry/project.hpp"

namespace facet::raster {

using geometry::kGuardBandPixels;
using geometry::kSubpixelBits;
using geometry::kSubpixelOne;
inline constexpr std::int32_t kPixelCentre = kSubpixelOne / 2;

// An attribute as an affine function of the pixel position (screen space, pixels, y down):
// f(x, y) = at_v0 + dx (x - x0) + dy (y - y0), where (x0, y0) is vertex 0. Depth is affine in
// screen space; perspective-correct attributes are interpolated as f/w and 1/w (both affine) and
// divided per pixel. The SIMD rasterizer evaluates these planes; the scalar one uses barycentrics.
struct Plane {
  float at_v0, dx, dy;
};
// Attributes interpolated per pixel at most (VaryingLayout::raster: Phong's position, normal,
// albedo and uv); clipping carries more (a two-sided draw's back-face values).
inline constexpr int kMaxRasterAttributes = 11;
// Planes of a triangle: depth, 1/w, then attribute a over w.
inline constexpr int kPlaneZ = 0, kPlaneInvW = 1, kPlaneAttr = 2;
inline constexpr int kPlaneCount = kPlaneAttr + kMaxRasterAttributes;

// Fields the rasterizers read come first (three cache lines, prefetched ahead of use); set-up
// also uses the rest. Both rasterizers interpolate attributes from the planes.
// One set-up triangle. The SIMD tile kernel reads the first fields (positions, bounds, draw,
// top-left bias, then the planes it interpolates: depth, 1/w, the first attributes): they come
// first, and records are 64-byte aligned, so a Gouraud triangle's kernel data is its first two
// cache lines (112 bytes). The scalar rasterizer's data comes last (its area from signed_area2).
struct alignas(64) ScreenTriangle {
  // Not zeroed: assembly writes every field a kernel reads (the planes up to its draw's layout),
  // and zeroing 256 bytes a record is a store stream placing does not need. zeroed() for tests.
  ScreenTriangle() noexcept {}
  static ScreenTriangle zeroed() noexcept {
    ScreenTriangle t;
    std::memset(static_cast<void*>(&t), 0, sizeof t);
    return t;
  }
  std::int32_t x[3], y[3];  // fixed point, oriented (area2 > 0)
  int min_px, min_py, max_px, max_py;  // covered pixel bounds, inclusive, inside the viewport
  float alpha;
  std::uint32_t object;
  std::int8_t bias[3];  // 0 on top-left edges, -1 on the others
  // kBackFacing, and kBitangentNegative: a normal-mapped draw's bitangent is -cross(normal,
  // tangent) (Varying::tangent_sign, with the back face's flip), the tangent frame mirrored. A
  // whole byte, not bit-fields: placing writes it without reading the new record's line first
  // (a bit-field's read-modify-write missed the cache on every placed triangle).
  std::uint8_t flags;
  static constexpr std::uint8_t kBackFacing = 1, kBitangentNegative = 2;
  bool back_facing() const { return flags & kBackFacing; }
  bool bitangent_negative() const { return flags & kBitangentNegative; }
  Plane plane[kPlaneCount];  // set by compute_planes
  float flat_rgb[3];
  float flat_secondary[3];  // flat shading of a textured draw: the specular, added after the texture
  // The scalar rasterizer's (coverage and depth), set by the scalar placing and by clipping;
  // records the SIMD placing kernel makes leave them unset (AssemblyFrame::place).
  float z[3];      // window depth, [0, 1]
  float inv_w[3];  // 1 / clip w, for perspective-correct interpolation
};
static_assert(sizeof(ScreenTriangle) == 256, "four cache lines; the kernel's fields in the first two");

inline bool is_top_left(std::int64_t dx, std::int64_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

// floor(a / b) for b > 0.
inline std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Twice the signed area of the snapped triangle: > 0 clockwise on the y-down screen.
inline std::int64_t signed_area2(std::int32_t x0, std::int32_t y0, std::int32_t x1, std::int32_t y1, std::int32_t x2,
                                 std::int32_t y2) {
  return (std::int64_t(x1) - x0) * (std::int64_t(y2) - y0) - (std::int64_t(x2) - x0) * (std::int64_t(y1) - y0);
}
inline std::int64_t signed_area2(const ScreenTriangle& t) {
  return signed_area2(t.x[0], t.y[0], t.x[1], t.y[1], t.x[2], t.y[2]);
}

// For a triangle with x, y set and signed_area2(t) > 0: sets area2, inv_area2, the top-left biases
// and the covered pixel bounds clipped to a width x height viewport: the pixels with a sample in
// the triangle's bounds, their samples at offsets sample_lo..sample_hi from the pixel's corner on
// either axis (the centre by default). False if no sample of the viewport can be covered.
bool finish_setup(ScreenTriangle& t, int width, int height, std::int32_t sample_lo = kPixelCentre,
                  std::int32_t sample_hi = kPixelCentre);

// After finish_setup: the planes of depth, 1/w and the first `attribute_count` (at most
// kMaxRasterAttributes) attributes over w, attr[k] being vertex k's, from the snapped vertex
// positions (so they agree with the coverage test), computed in double.
// z and inv_w: the oriented vertices' window depth and 1 / clip w (the record's own, or set-up's
// copy of them).
void compute_planes(ScreenTriangle& t, const float* z, const float* inv_w, const float (*attr)[geometry::kMaxAttributes],
                    int attribute_count);
inline void compute_planes(ScreenTriangle& t, const float (*attr)[geometry::kMaxAttributes], int attribute_count) {
  compute_planes(t, t.z, t.inv_w, attr, attribute_count);
}

// Edge k of a triangle with oriented fixed-point vertices x[3], y[3], from vertex k+1 to vertex
// k+2: E_k(p) = B (p.y - a.y) + A (p.x - a.x) with A = -(b.y - a.y), B = b.x - a.x, and its value
// biased by the top-left rule (bias[k]: 0 or -1) at the point (px, py) in 1/kSubpixelOne pixels.
// The one definition the scalar rasterizer, the SIMD tile kernel and the shadow volumes step from
// (whole pixels: A kSubpixelOne across, B kSubpixelOne down; exact in int64).
// In an unnamed namespace (and always inlined) as the SIMD kernels' code is: the per-ISA files
// include it, and one inline copy merged across their flags could run on a CPU without them.
struct Edge {
  std::int64_t A, B, at;
};
namespace {
[[gnu::always_inline]] inline Edge edge_at(const std::int32_t (&x)[3], const std::int32_t (&y)[3], const std::int8_t (&bias)[3], int k,
                    std::int64_t px, std::int64_t py) {
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  const std::int64_t A = -(std::int64_t(y[b]) - y[a]);
  const std::int64_t B = std::int64_t(x[b]) - x[a];
  return {A, B, B * (py - y[a]) + A * (px - x[a]) + bias[k]};
}
}  // namespace

// Calls fn(x, y, e0, e1, e2) for every covered pixel of `t` in [x0, x1] x [y0, y1] (inclusive,
// inside t's bounds), row by row, left to right; e_k are the unbiased edge values (barycentric
// weight k = e_k / area2). Edge k runs from vertex k+1 to vertex k+2:
//   E_k(p) = B_k (p.y - a.y) + A_k (p.x - a.x),  A_k = -(b.y - a.y),  B_k = b.x - a.x,
// evaluated exactly once per triangle and row and stepped by whole pixels (exact in int64).
// A pixel is covered when its point at (sx, sy) from its corner (1/kSubpixelOne pixel; the centre
// by default, a sample's position when multisampling) is.
template <class Fn>
void for_each_covered_pixel(const ScreenTriangle& t, int x0, int y0, int x1, int y1, Fn&& fn,
                            std::int32_t sx = kPixelCentre, std::int32_t sy = kPixelCentre) {
  std::int64_t row_e[3], step_x[3], step_y[3];
  const std::int64_t px = std::int64_t(x0) * kSubpixelOne + sx;
  const std::int64_t py = std::int64_t(y0) * kSubpixelOne + sy;
  for (int k = 0; k < 3; ++k) {
    const Edge e = edge_at(t.x, t.y, t.bias, k, px, py);
    row_e[k] = e.at;
    step_x[k] = e.A * kSubpixelOne;
    step_y[k] = e.B * kSubpixelOne;
  }
  for (int y = y0; y <= y1; ++y) {
    std::int64_t e0 = row_e[0], e1 = row_e[1], e2 = row_e[2];
    for (int x = x0; x <= x1; ++x, e0 += step_x[0], e1 += step_x[1], e2 += step_x[2]) {
      if ((e0 | e1 | e2) < 0) continue;  // some biased edge value is negative: outside
      fn(x, y, e0 - t.bias[0], e1 - t.bias[1], e2 - t.bias[2]);
    }
    row_e[0] += step_y[0];
    row_e[1] += step_y[1];
    row_e[2] += step_y[2];
  }
}

}  // namespace facet::raster
