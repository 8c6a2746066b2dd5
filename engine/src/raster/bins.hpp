// Internal: binning. Each set-up range lists its triangles' (tile, index) entries in triangle
// order; merge_ranges() appends the ranges to the tiles' bins in range order, so every bin lists
// its triangles in submission order whatever the schedule of the set-up was.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "facet/render.hpp"
#include "raster/place.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::raster {

// What happened to the triangles of one set-up range (see FrameStats for each counter).
struct TriangleCounts {
  std::uint64_t in = 0, nonfinite = 0, outside = 0, clipped = 0, culled = 0, degenerate = 0, small = 0, drawn = 0,
                bin_entries = 0;
  void add_to(FrameStats& s) const;
};

// What one set-up range produced besides its triangles: its bin entries (tile, index) in
// triangle order, and its counters. Kept from frame to frame.
struct RangeBinning {
  std::vector<std::uint32_t> tile, index;
  TriangleCounts counts;
  void clear();
};

// The tile grid of a pass.
struct BinGrid {
  int tile_size = 64, tiles_x = 0, tiles_y = 0;
};

// Adds the entries of triangle `index` of a range (its bounds set by finish_setup) to `out`.
void bin_triangle(const ScreenTriangle& t, std::uint32_t index, const BinGrid& grid, RangeBinning& out);

// Appends ranges [0, count) to `bins` in range order and adds their counters to `stats`.
void merge_ranges(std::span<const RangeBinning> ranges, std::size_t count, std::vector<std::vector<std::uint32_t>>& bins,
                  FrameStats& stats);

// The same merge in three steps, the first and last of which may run for different ranges on
// different threads (the bins come out as merge_ranges makes them, for any schedule):
//   count_range(ranges[r], row r)          entries of range r per tile, into its row of `offsets`
//   place_ranges(...)                      rows turned into each range's first slot in each bin,
//                                          bins sized, counters added to `stats` (one thread)
//   scatter_range(ranges[r], r, row r, bins)  range r's entries written from its slots on
// `offsets` holds one row of `tiles` counts per range.
void count_range(const RangeBinning& range, std::span<std::uint32_t> row);
void place_ranges(std::span<const RangeBinning> ranges, std::size_t count, std::span<std::uint32_t> offsets,
                  std::vector<std::vector<std::uint32_t>>& bins, FrameStats& stats);
void scatter_range(const RangeBinning& range, std::size_t r, std::span<std::uint32_t> row,
                   std::vector<std::vector<std::uint32_t>>& bins);

}  // namespace facet::raster
