// Internal: one screen tile, rasterized and resolved. The tile's colour (float RGBA) and depth live
// in a tile-local buffer that is cleared here; triangles are processed in bin order (= submission
// order), so the result does not depend on which task renders which tile.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "facet/render.hpp"
#include "lighting/point_shader.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::raster {

struct TileRect {
  int x0, y0, x1, y1;  // pixels, [x0, x1) x [y0, y1)
};

struct TileBuffers {
  int size = 0;
  std::vector<float> color;  // size * size * 4
  std::vector<float> depth;  // size * size
  void resize(int tile_size);
};

// Triangles are set up in parallel ranges; a bin entry names one as (range << 16) | index. A range
// holds at most 8192 input triangles, each clipped into at most 7 pieces (< 2^16).
inline constexpr int kRangeShift = 16;
inline constexpr std::uint32_t kIndexMask = (1u << kRangeShift) - 1;

struct RasterJob {
  ShadingMode shading;
  std::span<const std::vector<ScreenTriangle>> triangle_ranges;
  std::span<const lighting::PointShader> objects;  // per object, for per-pixel (Phong) lighting
  std::array<float, 4> clear_color;
};

struct RasterCounters {
  std::uint64_t tested = 0, filled = 0, shaded = 0;
  std::uint64_t light_pairs = 0, skipped_pairs = 0;  // per-pixel (Phong) lighting
  double seconds_resolve = 0;
  RasterCounters& operator+=(const RasterCounters& o) {
    tested += o.tested, filled += o.filled, shaded += o.shaded;
    light_pairs += o.light_pairs, skipped_pairs += o.skipped_pairs;
    seconds_resolve += o.seconds_resolve;
    return *this;
  }
};

// `tile` and `scratch` belong to the calling thread; the tile's pixels belong to this call.
void rasterize_tile(const RasterJob& job, std::span<const std::uint32_t> bin, const TileRect& rect,
                    TileBuffers& tile, lighting::SoaScratch& scratch, RasterCounters& counters);

// Writes the tile into the caller's views (already validated; depth may be null).
void resolve_tile(const TileBuffers& tile, const TileRect& rect, const ImageView& color, const DepthView* depth);

// A tile no triangle touches: writes the clear colour (converted exactly as resolve_tile would)
// and far depth straight into the caller's views, without the tile buffers.
void resolve_clear_tile(const std::array<float, 4>& clear_color, const TileRect& rect, const ImageView& color,
                        const DepthView* depth);

}  // namespace facet::raster
