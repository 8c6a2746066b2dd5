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

#include "geometry/clip.hpp"

namespace facet::raster {

inline constexpr int kSubpixelBits = 8;
inline constexpr std::int32_t kSubpixelOne = 1 << kSubpixelBits;
inline constexpr std::int32_t kPixelCentre = kSubpixelOne / 2;
inline constexpr float kGuardBandPixels = 32768.0f;

struct ScreenTriangle {
  std::int32_t x[3], y[3];  // fixed point, oriented (area2 > 0)
  std::int64_t bias[3];     // 0 on top-left edges, -1 on the others
  std::int64_t area2;
  float inv_area2;
  float z[3];      // window depth, [0, 1]
  float inv_w[3];  // 1 / clip w, for perspective-correct interpolation
  float attr[3][geometry::kMaxAttributes];
  float flat_rgb[3];
  float alpha;
  std::uint32_t object;
  bool back_facing;
  int min_px, min_py, max_px, max_py;  // covered pixel bounds, inclusive, inside the viewport
};

inline bool is_top_left(std::int64_t dx, std::int64_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

// floor(a / b) for b > 0.
inline std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace facet::raster
