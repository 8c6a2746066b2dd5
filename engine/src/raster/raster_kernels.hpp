// Internal: the SIMD tile rasterizer's interface. Plain data only (no Eigen, no standard
// containers): the kernels are compiled once per ISA and must not instantiate inline code the
// linker could merge across ISA files (shared/design/platform.md, trap 5).
//
// Tile memory is block-linear: each plane (R, G, B, A, depth) of a size x size tile is stored as
// 8x8 blocks of 64 floats (row-major inside a block, blocks row-major in the tile), so every SIMD
// width (4, 8 or 16 lanes) reads and writes whole contiguous batches, and a block is the unit of
// the hierarchical test: blocks outside a triangle are skipped with three compares, blocks inside
// it skip the edge tests, only blocks on an edge test their pixels.
#pragma once

#include <cstddef>
#include <cstdint>

#include "facet/image.hpp"
#include "raster/triangle_setup.hpp"
#include "raster/varyings.hpp"
#include "texture/sampler.hpp"

namespace facet::raster {
// Triangles are set up in parallel ranges; a bin entry names one as (range << 16) | index. A range
// holds at most 8192 input triangles, each clipped into at most 7 pieces (< 2^16).
inline constexpr int kRangeShift = 16;
inline constexpr std::uint32_t kIndexMask = (1u << kRangeShift) - 1;

}  // namespace facet::raster

namespace facet::raster::simd {

inline constexpr int kBlock = 8;  // block side in pixels
inline constexpr int kBlockPixels = kBlock * kBlock;

// Planes 0..3: colour R, G, B, A; plane 4: depth. `size` is a multiple of kBlock. Blocks are
// cleared lazily: `touched` (one byte per block) says which blocks hold data; the others are
// resolved straight from the clear colour, so a tile that a small triangle grazes costs little.
struct TileView {
  float* plane[5];
  std::uint8_t* touched;
  int size;
  float clear[4];
};

// Per-pixel (Phong) lighting: the kernel gathers the interpolated eye-space positions and normals
// of visible pixels into these structure-of-arrays buffers (capacity kPhongCapacity), then asks
// `shade` to light them with the shader of `object`; the colours come back in r, g, b.
inline constexpr int kPhongCapacity = 256;  // a multiple of the widest batch (16)
struct PhongSink {
  float *px, *py, *pz, *nx, *ny, *nz, *r, *g, *b;
  std::uint32_t* pixel;  // tile-buffer index of each entry
  void* context;
  // `padded` is `count` rounded up to 16; entries [count, padded) hold zeros.
  void (*shade)(void* context, std::uint32_t object, std::size_t count, std::size_t padded);
};

struct TileJob {
  int shading;  // ShadingMode as int
  const ScreenTriangle* const* ranges;  // set-up ranges; a bin entry is (range << 16) | index
  const std::uint32_t* bin;
  std::size_t bin_size;
  int x0, y0, x1, y1;  // the tile's pixels in the image, [x0, x1) x [y0, y1)
  PhongSink* phong;  // for ShadingMode::phong
  const VaryingLayout* varyings;  // where the planes of the colour (Gouraud) or position and normal (Phong) are
};

struct TileCounters {
  std::uint64_t tested = 0, filled = 0;
};

using RasterTileFunction = void (*)(const TileJob&, const TileView&, TileCounters&);
// Writes the tile's [x0, x1) x [y0, y1) into the caller's views (validated; depth may be null).
using ResolveTileFunction = void (*)(const TileView&, int x0, int y0, int x1, int y1, const ImageView&,
                                     const DepthView*);

// The ISA's texture sampler on planar streams: in = u, v, ds/dx, dt/dx, ds/dy, dt/dy; out = R, G, B, A.
using SampleTextureFunction = void (*)(const texture::Sampler&, std::size_t count, const float* const* in,
                                       float* const* out);

struct Kernels {
  RasterTileFunction raster;
  ResolveTileFunction resolve;
  SampleTextureFunction sample;
};

namespace sse2 {
void raster_tile(const TileJob&, const TileView&, TileCounters&);
void resolve_tile(const TileView&, int, int, int, int, const ImageView&, const DepthView*);
void sample_texture(const texture::Sampler&, std::size_t, const float* const*, float* const*);
}  // namespace sse2
namespace avx2 {
void raster_tile(const TileJob&, const TileView&, TileCounters&);
void resolve_tile(const TileView&, int, int, int, int, const ImageView&, const DepthView*);
void sample_texture(const texture::Sampler&, std::size_t, const float* const*, float* const*);
}  // namespace avx2
namespace avx512 {
void raster_tile(const TileJob&, const TileView&, TileCounters&);
void resolve_tile(const TileView&, int, int, int, int, const ImageView&, const DepthView*);
void sample_texture(const texture::Sampler&, std::size_t, const float* const*, float* const*);
}  // namespace avx512

}  // namespace facet::raster::simd
