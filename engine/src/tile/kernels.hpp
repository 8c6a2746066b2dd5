// Internal: the ISA kernel table: every kernel compiled once per ISA (kernels_sse2.cpp,
// kernels_avx2.cpp, kernels_avx512.cpp, each with its own flags and -ffp-contract=off) and the
// table the frame picks one ISA's from (simd_raster_kernels, tile_raster.hpp): the tile
// rasterizer and resolve (raster_simd.hpp, resolve_simd.hpp), the texture samplers
// (texture/sample_simd.hpp, texture/sample_fixed_simd.hpp), vertex transform and triangle placing
// (geometry/transform_simd.hpp, raster/place_simd.hpp), the shadow-map lookup
// (shadow/map_simd.hpp) and the display pass's store (display_simd.hpp). Plain data only, for the reason pixel/program.hpp gives.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "facet/display.hpp"
#include "facet/image.hpp"
#include "geometry/project.hpp"
#include "pixel/program.hpp"
#include "raster/place.hpp"
#include "shadow/map_lookup.hpp"
#include "texture/sampler.hpp"

namespace facet::tile::simd {

// The pixel program's contract (pixel/program.hpp), which the tile kernels run.
using pixel::Draw;
using pixel::Fog;
using pixel::kBlock;
using pixel::kBlockPixels;
using pixel::kMaxCarried;
using pixel::kPhongCapacity;
using pixel::kPhongStreams;
using pixel::PhongSink;
using pixel::PixelProgram;
using pixel::TileCounters;
using pixel::TileJob;
using pixel::TileView;
using raster::simd::PlaceFunction;
using raster::simd::PlaceGroup;
using raster::simd::PlaceParams;
using raster::simd::TransformFunction;

using RasterTileFunction = void (*)(const TileJob&, const TileView&, TileCounters&);
// Writes the tile's [x0, x1) x [y0, y1) into the caller's views (validated; depth may be null).
using ResolveTileFunction = void (*)(const TileView&, int x0, int y0, int x1, int y1, const ImageView&,
                                     const DepthView*);

// The ISA's texture sampler on planar streams: in = u, v, ds/dx, dt/dx, ds/dy, dt/dy; out = R, G, B, A.
using SampleTextureFunction = void (*)(const texture::Sampler&, std::size_t count, const float* const* in,
                                       float* const* out);
// The 16-bit tier's fixed-point sampler (texture/sample_fixed_simd.hpp) on the same inputs: packed
// RGBA8 per sample, the bytes sample_fixed_scalar returns.
using SampleFixedFunction = void (*)(const texture::Sampler&, std::size_t count, const float* const* in,
                                     std::uint32_t* out);

// One row of the display pass's 8-bit store (frame/display.cpp): the exposed float frame's row
// (RGBA, `width` pixels) and its depth, the background test's far depth and clear colour, the
// exposure scale and operator, the encoding (null: linear) and the output row (red at byte `red`:
// 0 for RGBA8, 2 for BGRA8).
struct DisplayRow {
  const float* rgba;
  const float* depth;
  int width;
  float far;
  float clear[4];
  float scale;
  ToneMapping tone_mapping;
  const SrgbTable* srgb;
  int red;
  std::uint8_t* dst;
};
// Stores the row's first pixels, a whole number of batches; returns how many (the caller stores
// the rest with the scalar loop).
using DisplayRowFunction = int (*)(const DisplayRow&);

struct Kernels {
  RasterTileFunction raster;
  ResolveTileFunction resolve;
  SampleTextureFunction sample;
  TransformFunction transform;
  PlaceFunction place;
  shadow::MapVisibilityFunction shadow_map;
  SampleFixedFunction sample_fixed;
  DisplayRowFunction display_row;
};

namespace sse2 {
void transform_vertices(const geometry::Mat4Rows&, const float*, std::size_t, std::size_t, const geometry::ClipPlanes&,
                        const geometry::Viewport&, std::array<float, 4>*, geometry::ScreenVertex*);
void place_triangles(const std::uint32_t*, const geometry::ScreenVertex*, const PlaceParams&, PlaceGroup&);
void raster_tile(const TileJob&, const TileView&, TileCounters&);
void resolve_tile(const TileView&, int, int, int, int, const ImageView&, const DepthView*);
void sample_texture(const texture::Sampler&, std::size_t, const float* const*, float* const*);
void sample_fixed(const texture::Sampler&, std::size_t, const float* const*, std::uint32_t*);
int display_row(const DisplayRow&);
void shadow_map(const shadow::MapLookup&, std::size_t, const float*, const float*, const float*, const float*,
                const float*, const float*, std::size_t, float*);
}  // namespace sse2
namespace avx2 {
void transform_vertices(const geometry::Mat4Rows&, const float*, std::size_t, std::size_t, const geometry::ClipPlanes&,
                        const geometry::Viewport&, std::array<float, 4>*, geometry::ScreenVertex*);
void place_triangles(const std::uint32_t*, const geometry::ScreenVertex*, const PlaceParams&, PlaceGroup&);
void raster_tile(const TileJob&, const TileView&, TileCounters&);
void resolve_tile(const TileView&, int, int, int, int, const ImageView&, const DepthView*);
void sample_texture(const texture::Sampler&, std::size_t, const float* const*, float* const*);
void sample_fixed(const texture::Sampler&, std::size_t, const float* const*, std::uint32_t*);
int display_row(const DisplayRow&);
void shadow_map(const shadow::MapLookup&, std::size_t, const float*, const float*, const float*, const float*,
                const float*, const float*, std::size_t, float*);
}  // namespace avx2
namespace avx512 {
void transform_vertices(const geometry::Mat4Rows&, const float*, std::size_t, std::size_t, const geometry::ClipPlanes&,
                        const geometry::Viewport&, std::array<float, 4>*, geometry::ScreenVertex*);
void place_triangles(const std::uint32_t*, const geometry::ScreenVertex*, const PlaceParams&, PlaceGroup&);
void raster_tile(const TileJob&, const TileView&, TileCounters&);
void resolve_tile(const TileView&, int, int, int, int, const ImageView&, const DepthView*);
void sample_texture(const texture::Sampler&, std::size_t, const float* const*, float* const*);
void sample_fixed(const texture::Sampler&, std::size_t, const float* const*, std::uint32_t*);
int display_row(const DisplayRow&);
void shadow_map(const shadow::MapLookup&, std::size_t, const float*, const float*, const float*, const float*,
                const float*, const float*, std::size_t, float*);
}  // namespace avx512

}  // namespace facet::tile::simd
