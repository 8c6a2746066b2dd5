#include "raster/tile_raster.hpp"

#include <algorithm>
#include <cstring>

#include "io/image_convert.hpp"

namespace facet::raster {

void TileBuffers::resize(int tile_size) {
  size = tile_size;
  const auto n = static_cast<std::size_t>(tile_size) * static_cast<std::size_t>(tile_size);
  color.resize(4 * n);
  depth.resize(n);
}

namespace {

// Phong pixels of one triangle, lit in batches by the lighting kernel.
class PixelBatch {
 public:
  static constexpr int kCapacity = 64;
  explicit PixelBatch(lighting::SoaScratch& scratch) : scratch_(scratch) {}

  void add(int index, const Vec3& p, const Vec3& n) {
    index_[count_] = index;
    p_[count_] = p;
    n_[count_] = n;
    ++count_;
  }
  bool full() const { return count_ == kCapacity; }

  void flush(const lighting::PointShader& shader, float alpha, TileBuffers& tile, RasterCounters& counters) {
    if (count_ == 0) return;
    shader.shade_points(static_cast<std::size_t>(count_), p_, n_, out_, scratch_);
    for (int i = 0; i < count_; ++i) {
      float* c = &tile.color[4 * static_cast<std::size_t>(index_[i])];
      c[0] = out_[i].x();
      c[1] = out_[i].y();
      c[2] = out_[i].z();
      c[3] = alpha;
    }
    counters.shaded += static_cast<std::uint64_t>(count_);
    counters.light_pairs += static_cast<std::uint64_t>(count_) * shader.light_count();
    counters.skipped_pairs += static_cast<std::uint64_t>(count_) * shader.culled_lights();
    count_ = 0;
  }

 private:
  int count_ = 0;
  int index_[kCapacity];
  Vec3 p_[kCapacity], n_[kCapacity];
  Color3 out_[kCapacity];
  lighting::SoaScratch& scratch_;
};

}  // namespace

void rasterize_tile(const RasterJob& job, std::span<const std::uint32_t> bin, const TileRect& rect,
                    TileBuffers& tile, lighting::SoaScratch& scratch, RasterCounters& counters) {
  const int stride = tile.size;
  for (int y = rect.y0; y < rect.y1; ++y) {
    const std::size_t row = static_cast<std::size_t>(y - rect.y0) * static_cast<std::size_t>(stride);
    for (int x = 0; x < rect.x1 - rect.x0; ++x) {
      std::memcpy(&tile.color[4 * (row + static_cast<std::size_t>(x))], job.clear_color.data(), 4 * sizeof(float));
      tile.depth[row + static_cast<std::size_t>(x)] = 1.0f;
    }
  }

  PixelBatch batch(scratch);
  for (const std::uint32_t entry : bin) {
    const ScreenTriangle& t = job.triangle_ranges[entry >> kRangeShift][entry & kIndexMask];
    const int x0 = std::max(t.min_px, rect.x0), x1 = std::min(t.max_px, rect.x1 - 1);
    const int y0 = std::max(t.min_py, rect.y0), y1 = std::min(t.max_py, rect.y1 - 1);
    if (x0 > x1 || y0 > y1) continue;

    const lighting::PointShader& shading = job.objects[t.object];
    for_each_covered_pixel(t, x0, y0, x1, y1, [&](int x, int y, std::int64_t e0, std::int64_t e1, std::int64_t e2) {
      ++counters.tested;
      const float l0 = static_cast<float>(e0) * t.inv_area2;
      const float l1 = static_cast<float>(e1) * t.inv_area2;
      const float l2 = static_cast<float>(e2) * t.inv_area2;
      float z = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
      z = z > 0.0f ? (z < 1.0f ? z : 1.0f) : 0.0f;
      const int pixel = (y - rect.y0) * stride + (x - rect.x0);
      if (!(z < tile.depth[static_cast<std::size_t>(pixel)])) return;  // depth test: LESS
      tile.depth[static_cast<std::size_t>(pixel)] = z;
      ++counters.filled;
      float* c = &tile.color[4 * static_cast<std::size_t>(pixel)];
      if (job.shading == ShadingMode::flat) {
        c[0] = t.flat_rgb[0];
        c[1] = t.flat_rgb[1];
        c[2] = t.flat_rgb[2];
        c[3] = t.alpha;
        return;
      }
      // Perspective-correct weights: (l_k / w_k) / sum(l_j / w_j).
      const float m0 = l0 * t.inv_w[0], m1 = l1 * t.inv_w[1], m2 = l2 * t.inv_w[2];
      const float inv_sum = 1.0f / (m0 + m1 + m2);
      const float w0 = m0 * inv_sum, w1 = m1 * inv_sum, w2 = m2 * inv_sum;
      auto interp = [&](int a) { return w0 * t.attr[0][a] + w1 * t.attr[1][a] + w2 * t.attr[2][a]; };
      if (job.shading == ShadingMode::gouraud) {
        c[0] = interp(0);
        c[1] = interp(1);
        c[2] = interp(2);
        c[3] = t.alpha;
      } else {
        batch.add(pixel, Vec3(interp(0), interp(1), interp(2)), Vec3(interp(3), interp(4), interp(5)));
        if (batch.full()) batch.flush(shading, t.alpha, tile, counters);
      }
    });
    batch.flush(shading, t.alpha, tile, counters);
  }
}

void resolve_tile(const TileBuffers& tile, const TileRect& rect, const ImageView& color, const DepthView* depth) {
  const std::size_t bpp = bytes_per_pixel(color.format);
  for (int y = rect.y0; y < rect.y1; ++y) {
    const int image_row = color.y_up ? color.height - 1 - y : y;
    auto* dst = static_cast<std::uint8_t*>(color.data) + static_cast<std::size_t>(image_row) * color.stride_bytes +
                static_cast<std::size_t>(rect.x0) * bpp;
    const float* src = &tile.color[4 * static_cast<std::size_t>(y - rect.y0) * static_cast<std::size_t>(tile.size)];
    const int n = rect.x1 - rect.x0;
    switch (color.format) {
      case PixelFormat::rgba8:
        for (int i = 0; i < 4 * n; ++i) dst[i] = to_unorm8(src[i]);
        break;
      case PixelFormat::bgra8:
        for (int x = 0; x < n; ++x) {
          dst[4 * x + 0] = to_unorm8(src[4 * x + 2]);
          dst[4 * x + 1] = to_unorm8(src[4 * x + 1]);
          dst[4 * x + 2] = to_unorm8(src[4 * x + 0]);
          dst[4 * x + 3] = to_unorm8(src[4 * x + 3]);
        }
        break;
      case PixelFormat::rgba32f: std::memcpy(dst, src, static_cast<std::size_t>(n) * 16); break;
    }
    if (depth) {
      const int depth_row = depth->y_up ? depth->height - 1 - y : y;
      auto* d = reinterpret_cast<std::uint8_t*>(depth->data) + static_cast<std::size_t>(depth_row) * depth->stride_bytes +
                static_cast<std::size_t>(rect.x0) * sizeof(float);
      std::memcpy(d, &tile.depth[static_cast<std::size_t>(y - rect.y0) * static_cast<std::size_t>(tile.size)],
                  static_cast<std::size_t>(n) * sizeof(float));
    }
  }
}

void resolve_clear_tile(const std::array<float, 4>& clear_color, const TileRect& rect, const ImageView& color,
                        const DepthView* depth) {
  // One pixel in the output format, converted by the same code as resolve_tile.
  std::uint8_t pixel[16];
  const std::size_t bpp = bytes_per_pixel(color.format);
  switch (color.format) {
    case PixelFormat::rgba8:
      for (int c = 0; c < 4; ++c) pixel[c] = to_unorm8(clear_color[static_cast<std::size_t>(c)]);
      break;
    case PixelFormat::bgra8:
      pixel[0] = to_unorm8(clear_color[2]);
      pixel[1] = to_unorm8(clear_color[1]);
      pixel[2] = to_unorm8(clear_color[0]);
      pixel[3] = to_unorm8(clear_color[3]);
      break;
    case PixelFormat::rgba32f: std::memcpy(pixel, clear_color.data(), 16); break;
  }
  const float far_depth = 1.0f;
  for (int y = rect.y0; y < rect.y1; ++y) {
    const int image_row = color.y_up ? color.height - 1 - y : y;
    auto* dst = static_cast<std::uint8_t*>(color.data) + static_cast<std::size_t>(image_row) * color.stride_bytes +
                static_cast<std::size_t>(rect.x0) * bpp;
    for (int x = rect.x0; x < rect.x1; ++x, dst += bpp) std::memcpy(dst, pixel, bpp);
    if (depth) {
      const int depth_row = depth->y_up ? depth->height - 1 - y : y;
      auto* d = reinterpret_cast<std::uint8_t*>(depth->data) + static_cast<std::size_t>(depth_row) * depth->stride_bytes +
                static_cast<std::size_t>(rect.x0) * sizeof(float);
      for (int x = rect.x0; x < rect.x1; ++x, d += sizeof(float)) std::memcpy(d, &far_depth, sizeof far_depth);
    }
  }
}

}  // namespace facet::raster
