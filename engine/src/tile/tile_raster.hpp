// Internal: one screen tile, rasterized and resolved. The tile's colour (float R, G, B, A planes)
// and depth live in tile-local, block-linear buffers (pixel/program.hpp) that are cleared here;
// triangles are processed in bin order (= submission order), so the result does not depend on
// which task renders which tile. Two rasterizers fill them: the scalar one below (the twin the
// SIMD kernels are tested against, used by the reference and scalar paths) and the SIMD kernels
// (raster_simd.hpp, used by the simd path).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "facet/render.hpp"
#include "lighting/point_shader.hpp"
#include "tile/backdrop.hpp"
#include "tile/kernels.hpp"
#include "raster/samples.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::tile {

using raster::SamplePattern;
using raster::ScreenTriangle;

struct TileRect {
  int x0, y0, x1, y1;  // pixels, [x0, x1) x [y0, y1)
};

struct TileBuffers {
  int size = 0;
  int samples = 1;  // per pixel: each plane holds `samples` runs of size * size floats, sample after sample
  // Five planes of `samples` runs, 64-byte aligned. Each run and each plane is followed by one
  // block of padding (kPlanePad floats): runs and planes a power of two apart (16 KiB for 64-pixel
  // tiles) would all fall in the same L1 sets, and a multisampled batch touches 5 x samples of
  // them at once.
  std::vector<float> storage;
  std::vector<float> phong;    // Phong sink buffers: kPhongStreams x kPhongCapacity
  std::vector<std::uint32_t> phong_pixel;
  std::vector<std::uint32_t> phong_samples;  // multisampled: the Phong sink's sample masks
  std::vector<std::uint8_t> touched;  // per block, for the SIMD kernels' lazy clear
  void resize(int tile_size, int sample_count = 1);
  float* plane(int c) { return storage.data() + offset_ + static_cast<std::size_t>(c) * plane_size_; }
  const float* plane(int c) const { return storage.data() + offset_ + static_cast<std::size_t>(c) * plane_size_; }
  simd::TileView view(const std::array<float, 4>& clear, const geometry::DepthFormat& depth, const SrgbTable* srgb = nullptr,
                      const SamplePattern* pattern = nullptr) {
    simd::TileView v{{plane(0), plane(1), plane(2), plane(3), plane(4)}, touched.data(), size, {clear[0], clear[1], clear[2], clear[3]},
                     srgb, depth.lo(), depth.far(), depth.reversed};
    if (pattern && pattern->count > 1) {
      v.samples = pattern->count;
      v.sample_stride = sample_stride();
      v.sample_x = pattern->x;
      v.sample_y = pattern->y;
    }
    return v;
  }
  // Floats between a pixel's consecutive samples in a plane.
  std::size_t sample_stride() const { return sample_stride_; }
  static constexpr std::size_t kPlanePad = simd::kBlockPixels;
  // Block-linear index of tile pixel (x, y).
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>((y / simd::kBlock) * (size / simd::kBlock) + x / simd::kBlock) *
               simd::kBlockPixels +
           static_cast<std::size_t>((y % simd::kBlock) * simd::kBlock + x % simd::kBlock);
  }

 private:
  std::size_t offset_ = 0, plane_size_ = 0, sample_stride_ = 0;
};

struct RasterJob {
  ShadingMode shading;
  const ScreenTriangle* const* ranges;  // the triangles of each set-up range (a bin entry names one)
  std::span<const lighting::PointShader> objects;  // per object, for per-pixel (Phong) lighting
  std::array<float, 4> clear_color;
  const simd::Kernels* kernels;  // the SIMD rasterizer of the chosen ISA; null: the scalar one
  const simd::Draw* draws;        // per ScreenTriangle::object: its varying layout and pixel program
  const simd::Fog* fog;
  const SrgbTable* srgb;          // when 8-bit output is sRGB-encoded, else null
  geometry::DepthFormat depth;    // how the pass stores depth (the viewport's)
  SamplePattern samples{};        // the pass's samples per pixel (one: the centre)
  const Backdrop* backdrop = nullptr;  // the clear value per pixel instead of clear_color (tile/backdrop.hpp)
};

// The SIMD rasterizer of an ISA (Isa::best resolved), or null if this CPU lacks it.
const simd::Kernels* simd_raster_kernels(Isa isa) noexcept;

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

// Writes the tile into the caller's views (already validated; depth may be null), with the job's
// kernels or the scalar code: both convert exactly as to_unorm8.
void resolve_tile(const RasterJob& job, TileBuffers& tile, const TileRect& rect, const ImageView& color,
                  const DepthView* depth);

// A depth-only pass's tile: its depth into `depth` (far depth where no triangle was drawn; the
// SIMD kernels clear a block only when a triangle first reaches it).
void resolve_depth_tile(const RasterJob& job, const TileBuffers& tile, const TileRect& rect, const DepthView& depth);
// A depth-only pass's tile no triangle touches: far depth.
void resolve_clear_depth(const TileRect& rect, const DepthView& depth);

// One RGBA float pixel in an output format: 8-bit channels as to_unorm8 (sRGB-encoded colour with
// `srgb`), floats as they are.
void store_pixel(const float* rgba, PixelFormat format, const SrgbTable* srgb, std::uint8_t* dst);

// A tile no triangle touches: writes the clear colour (converted exactly as resolve_tile would)
// and far depth (`far_depth`, in the output's convention) straight into the caller's views,
// without the tile buffers.
void resolve_clear_tile(const std::array<float, 4>& clear_color, const SrgbTable* srgb, const TileRect& rect,
                        const ImageView& color, const DepthView* depth, float far_depth);

}  // namespace facet::tile
