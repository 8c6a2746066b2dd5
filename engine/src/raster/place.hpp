// Internal: the SIMD tile rasterizer's interface. Plain data only (no Eigen, no standard
// containers): the kernels are compiled once per ISA and must not instantiate inline code the
// linker could merge across ISA files (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
//
// Tile memory is block-linear: each plane (R, G, B, A, depth) of a size x size tile is stored as
// 8x8 blocks of 64 floats (row-major inside a block, blocks row-major in the tile), so every SIMD
// width (4, 8 or 16 lanes) reads and writes whole contiguous batches, and a block is the unit of
// the hierarchical test: blocks outside a triangle are skipped with three compares, blocks inside
// it skip the edge tests, only blocks on an edge test their pixels.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "geometry/project.hpp"

namespace facet::raster {
// Triangles are set up in parallel ranges; a bin entry names one as (range << 16) | index. A range
// holds at most 8192 input triangles, each clipped into at most 7 pieces (< 2^16).
inline constexpr int kRangeShift = 16;
inline constexpr std::uint32_t kIndexMask = (1u << kRangeShift) - 1;

}  // namespace facet::raster

namespace facet::raster::simd {

// geometry::transform_vertices on the ISA (bit-identical to it); positions are xyz triples.
using TransformFunction = void (*)(const geometry::Mat4Rows&, const float* positions, std::size_t begin, std::size_t end,
                                   const geometry::ClipPlanes&, const geometry::Viewport&, std::array<float, 4>* clip,
                                   geometry::ScreenVertex* screen);

// Placing (raster/assemble.hpp) kPlaceGroup triangles at a time: each triangle's fate, and for
// the placed ones their oriented screen vertices, covered pixel bounds, top-left biases and facing,
// exactly as the scalar twin (RangeAssembler's per-triangle placing) computes them. Lanes the
// kernel does not decide (an edge spanning 2^15 sub-pixels or more, see place_simd.hpp) are
// `scalar`: the caller places those triangles with the scalar code.
inline constexpr int kPlaceGroup = 16;
struct PlaceGroup {
  enum Fate : std::int32_t { nonfinite, outside, clip, culled, degenerate, small, placed, placed_swapped, scalar };
  static constexpr int kFates = scalar + 1;
  alignas(64) std::int32_t fate[kPlaceGroup];
  // Bit l: lane l is placed, clipped or handed back to the scalar code (the lanes to take; the
  // fields below are written for groups of W lanes with one such lane at least). Lanes per fate.
  std::uint32_t keep;
  std::int32_t count[kFates];
  alignas(64) std::int32_t x[3][kPlaceGroup], y[3][kPlaceGroup];  // oriented (area2 > 0)
  alignas(64) float z[3][kPlaceGroup], inv_w[3][kPlaceGroup];
  alignas(64) std::int32_t min_px[kPlaceGroup], min_py[kPlaceGroup], max_px[kPlaceGroup], max_py[kPlaceGroup];
  alignas(64) std::int32_t bias[3][kPlaceGroup];  // 0 or -1
  alignas(64) std::int32_t back_facing[kPlaceGroup];  // 0 or 1
};
struct PlaceParams {
  int width, height;                  // the viewport
  bool cull_back, cull_front;         // which facing is culled (CullMode and two-sidedness folded in)
  bool mirrored;                      // the object's front faces wind clockwise on screen
  std::int32_t sample_lo, sample_hi;  // geometry::Viewport's sample offsets (finish_setup)
};
// `triangles`: kPlaceGroup vertex-index triples; `screen`: the object's screen vertices, fewer than
// 2^31 / 5 of them (gathers index 32-bit words).
using PlaceFunction = void (*)(const std::uint32_t* triangles, const geometry::ScreenVertex* screen,
                               const PlaceParams&, PlaceGroup&);

}  // namespace facet::raster::simd
