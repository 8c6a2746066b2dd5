// A pass after its draws are set up: the ranges' bins merged in order, then the tile loop: each
// tile is rasterized and resolved by exactly one task, from its bin (in submission order) into its
// own pixels, so the image does not depend on the schedule.
#include <algorithm>

#include <tbb/blocked_range.h>

#include "frame/frame.hpp"

namespace facet {

void Renderer::Impl::run_pass(const Scene& scene, const RenderOptions& options, const RenderPass& p,
                              std::span<const DrawUnit> pass_draws) {
  pass = &p;
  units = pass_draws;
  // Grow only: a frame's passes differ in tile count, and a shrunk bin would give its capacity up.
  if (bins.size() < static_cast<std::size_t>(p.tile_count())) bins.resize(static_cast<std::size_t>(p.tile_count()));
  for (int t = 0; t < p.tile_count(); ++t) bins[static_cast<std::size_t>(t)].clear();
  frame::plan_draws(scene, options, p, units, kind, samplers, targets.cubes, draws);
  fog = frame::plan_fog(kind.plain() ? Fog{} : kind.lights_of(scene).fog);
  set_up_objects(scene, options);
  const int tiles_x = p.tiles_x, tile_size = p.tile_size;
  if (cancelled.load(std::memory_order_relaxed)) return;  // before any pixel is written

  // Counters are kept per tile and added up in tile order afterwards.
  const auto merge_start = Clock::now();
  merge_bins();
  if (!p.depth_only) stats.seconds_geometry += seconds_since(merge_start);
  range_data.resize(range_count);
  for (std::size_t r = 0; r < range_count; ++r) range_data[r] = range_triangles[r].data();
  const tile::RasterJob job{p.shading,
                              range_data.data(),
                              shaders,
                              p.clear_color,
                              simd_kernels,
                              draws.programs.data(),
                              &fog,
                              options.srgb && p.color && p.color->format != PixelFormat::rgba32f && !p.environment_face ? &srgb : nullptr,
                              p.assembly.viewport.depth,
                              p.samples,
                              frame_backdrop && &p == &plan.camera().pass ? &*frame_backdrop : nullptr};
  const int tile_count = p.tile_count();
  tile_counters.assign(static_cast<std::size_t>(tile_count), {});
  const auto raster_start = Clock::now();
  arena->parallel_for(tbb::blocked_range<int>(0, tile_count), [&](const tbb::blocked_range<int>& range, int slot) {
    WorkerScratch& w = worker(slot);
    for (int index = range.begin(); index != range.end(); ++index) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      const int tx = index % tiles_x, ty = index / tiles_x;
      const tile::TileRect rect{tx * tile_size, ty * tile_size, std::min(p.width(), (tx + 1) * tile_size),
                                  std::min(p.height(), (ty + 1) * tile_size)};
      tile::RasterCounters& c = tile_counters[static_cast<std::size_t>(index)];
      const auto& bin = bins[static_cast<std::size_t>(index)];
      if (p.depth_only) {  // a shadow map's face: depth alone
        std::uint8_t& dirty = p.depth_dirty[index];
        if (bin.empty()) {
          if (dirty) tile::resolve_clear_depth(rect, *p.depth);  // else still far depth from an earlier frame
          dirty = 0;
        } else {
          tile::rasterize_tile(job, bin, rect, w.tile, w.soa, c);
          tile::resolve_depth_tile(job, w.tile, rect, *p.depth);
          dirty = 1;
        }
        unit_done();
        continue;
      }
      if (bin.empty()) {  // nothing to rasterize: the clear colour (or backdrop) goes straight to the image
        const auto resolve_start = Clock::now();
        if (job.backdrop) {
          tile::resolve_backdrop_tile(*job.backdrop, job.srgb, rect, *p.color, p.depth, job.depth.output(job.depth.far()));
        } else {
          tile::resolve_clear_tile(p.clear_color, job.srgb, rect, *p.color, p.depth, job.depth.output(job.depth.far()));
        }
        c.seconds_resolve = seconds_since(resolve_start);
        continue;
      }
      tile::rasterize_tile(job, bin, rect, w.tile, w.soa, c);
      const auto resolve_start = Clock::now();
      tile::resolve_tile(job, w.tile, rect, *p.color, p.depth);
      c.seconds_resolve = seconds_since(resolve_start);
      unit_done();
    }
  });
  stats.seconds_raster = seconds_since(raster_start);
  tile::RasterCounters counters;
  for (const tile::RasterCounters& c : tile_counters) counters += c;  // in tile order
  if (p.depth_only) {
    if (p.casters_only) stats.shadow_map_pixels += counters.filled;
    return;
  }
  stats.seconds_resolve = counters.seconds_resolve;
  stats.pixels_tested = counters.tested;
  stats.pixels_filled = counters.filled;
  stats.vertices_lit += counters.shaded;
  stats.vertex_lights_evaluated += counters.light_pairs;
  stats.vertex_lights_skipped += counters.skipped_pairs;
}

// The ranges' bin entries appended to the tiles' bins in range order. With many entries the
// count and the scatter run in parallel over the ranges (bins::count_range): a serial merge was
// the frame's largest serial step on a million-triangle mesh. Where the per-range counts would
// outweigh the entries (many tiles, few triangles), the serial merge.
void Renderer::Impl::merge_bins() {
  std::size_t entries = 0;
  for (std::size_t r = 0; r < range_count; ++r) entries += range_binning[r].tile.size();
  const std::size_t tiles = bins.size();
  if (entries < (std::size_t{1} << 16) || range_count < 2 || range_count * tiles > entries) {
    raster::merge_ranges(range_binning, range_count, bins, stats);
    return;
  }
  if (merge_offsets.size() < range_count * tiles) merge_offsets.resize(range_count * tiles);
  auto row = [&](std::size_t r) { return std::span<std::uint32_t>(merge_offsets.data() + r * tiles, tiles); };
  arena->parallel_for(tbb::blocked_range<std::size_t>(0, range_count, 4), [&](const tbb::blocked_range<std::size_t>& rs, int) {
    for (std::size_t r = rs.begin(); r != rs.end(); ++r) raster::count_range(range_binning[r], row(r));
  });
  raster::place_ranges(range_binning, range_count, merge_offsets, bins, stats);
  arena->parallel_for(tbb::blocked_range<std::size_t>(0, range_count, 4), [&](const tbb::blocked_range<std::size_t>& rs, int) {
    for (std::size_t r = rs.begin(); r != rs.end(); ++r) raster::scatter_range(range_binning[r], r, row(r), bins);
  });
}

}  // namespace facet
