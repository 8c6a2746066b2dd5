#include "raster/bins.hpp"

#include <algorithm>

namespace facet::raster {

void TriangleCounts::add_to(FrameStats& s) const {
  s.triangles_in += in;
  s.triangles_nonfinite += nonfinite;
  s.triangles_outside += outside;
  s.triangles_clipped += clipped;
  s.triangles_culled += culled;
  s.triangles_degenerate += degenerate;
  s.triangles_small += small;
  s.triangles_drawn += drawn;
  s.bin_entries += bin_entries;
}

void RangeBinning::clear() {
  tile.clear();
  index.clear();
  counts = TriangleCounts{};
}

void bin_triangle(const ScreenTriangle& t, std::uint32_t index, const BinGrid& grid, RangeBinning& out) {
  ++out.counts.drawn;
  for (int ty = t.min_py / grid.tile_size; ty <= t.max_py / grid.tile_size; ++ty) {
    for (int tx = t.min_px / grid.tile_size; tx <= t.max_px / grid.tile_size; ++tx) {
      out.tile.push_back(static_cast<std::uint32_t>(ty * grid.tiles_x + tx));
      out.index.push_back(index);
      ++out.counts.bin_entries;
    }
  }
}

void merge_ranges(std::span<const RangeBinning> ranges, std::size_t count, std::vector<std::vector<std::uint32_t>>& bins,
                  FrameStats& stats) {
  for (std::size_t r = 0; r < count; ++r) {
    const RangeBinning& rb = ranges[r];
    const auto high = static_cast<std::uint32_t>(r) << kRangeShift;
    for (std::size_t e = 0; e < rb.tile.size(); ++e) bins[rb.tile[e]].push_back(high | rb.index[e]);
    rb.counts.add_to(stats);
  }
}

void count_range(const RangeBinning& range, std::span<std::uint32_t> row) {
  std::fill(row.begin(), row.end(), 0u);
  for (const std::uint32_t t : range.tile) ++row[t];
}

void place_ranges(std::span<const RangeBinning> ranges, std::size_t count, std::span<std::uint32_t> offsets,
                  std::vector<std::vector<std::uint32_t>>& bins, FrameStats& stats) {
  const std::size_t tiles = bins.size();
  std::vector<std::uint32_t> running(tiles);
  for (std::size_t t = 0; t < tiles; ++t) running[t] = static_cast<std::uint32_t>(bins[t].size());
  for (std::size_t r = 0; r < count; ++r) {
    std::uint32_t* row = offsets.data() + r * tiles;
    for (std::size_t t = 0; t < tiles; ++t) {
      const std::uint32_t n = row[t];
      row[t] = running[t];
      running[t] += n;
    }
    ranges[r].counts.add_to(stats);
  }
  for (std::size_t t = 0; t < tiles; ++t) bins[t].resize(running[t]);
}

void scatter_range(const RangeBinning& range, std::size_t r, std::span<std::uint32_t> row,
                   std::vector<std::vector<std::uint32_t>>& bins) {
  const auto high = static_cast<std::uint32_t>(r) << kRangeShift;
  for (std::size_t e = 0; e < range.tile.size(); ++e) {
    const std::uint32_t t = range.tile[e];
    bins[t][row[t]++] = high | range.index[e];
  }
}

}  // namespace facet::raster
