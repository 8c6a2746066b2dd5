#include "io/rows.hpp"
#include "tile/tile_raster.hpp"

#include <algorithm>
#include <cstring>

#include "io/image_convert.hpp"
#include "io/srgb.hpp"

#include <emmintrin.h>
#include "pixel/stages.hpp"
#include "texture/sampler.hpp"

namespace facet::tile {

namespace stages = facet::pixel;  // the pixel stages (a local here is named pixel)
using namespace facet::raster;   // the set-up's records (ScreenTriangle, planes, varyings) it rasterizes

void TileBuffers::resize(int tile_size, int sample_count) {
  size = tile_size;
  samples = sample_count;
  sample_stride_ = static_cast<std::size_t>(tile_size) * static_cast<std::size_t>(tile_size) + kPlanePad;
  plane_size_ = static_cast<std::size_t>(sample_count) * sample_stride_ + kPlanePad;  // multiples of 16 floats
  storage.resize(5 * plane_size_ + 16);  // grows only; + slack for the alignment below
  const auto address = reinterpret_cast<std::uintptr_t>(storage.data());
  offset_ = ((64 - address % 64) % 64) / sizeof(float);
  // The sink's streams, then the shadowed lights' visibility of its pixels, then the projectors' filters.
  phong.resize((simd::kPhongStreams + lighting::kMaxShadowedLights + 3 * kMaxProjectors) *
               static_cast<std::size_t>(simd::kPhongCapacity));
  phong_pixel.resize(simd::kPhongCapacity);
  phong_samples.resize(simd::kPhongCapacity);
  touched.resize(static_cast<std::size_t>(tile_size / simd::kBlock) * static_cast<std::size_t>(tile_size / simd::kBlock));
}

const simd::Kernels* simd_raster_kernels(Isa isa) noexcept {
  static constexpr simd::Kernels sse2{simd::sse2::raster_tile, simd::sse2::resolve_tile, simd::sse2::sample_texture,
                                            simd::sse2::transform_vertices, simd::sse2::place_triangles,
                                            simd::sse2::shadow_map, simd::sse2::sample_fixed, simd::sse2::display_row};
  static constexpr simd::Kernels avx2{simd::avx2::raster_tile, simd::avx2::resolve_tile, simd::avx2::sample_texture,
                                            simd::avx2::transform_vertices, simd::avx2::place_triangles,
                                            simd::avx2::shadow_map, simd::avx2::sample_fixed, simd::avx2::display_row};
  static constexpr simd::Kernels avx512{simd::avx512::raster_tile, simd::avx512::resolve_tile, simd::avx512::sample_texture,
                                            simd::avx512::transform_vertices, simd::avx512::place_triangles,
                                            simd::avx512::shadow_map, simd::avx512::sample_fixed, simd::avx512::display_row};
  if (isa == Isa::best) isa = best_isa();
  if (!isa_supported(isa)) return nullptr;
  switch (isa) {
    case Isa::sse2: return &sse2;
    case Isa::avx2: return &avx2;
    case Isa::avx512: return &avx512;
    case Isa::best: break;
  }
  return nullptr;
}

namespace {

// A map at (u, v) on its level 0 (environment maps: texgen coordinates have no derivatives).
void level0(const texture::Sampler& sampler, float u, float v, float (&rgba)[4]) {
  const auto texel = texture::sample_scalar(sampler, u, v, 0.0f);
  for (int c = 0; c < 4; ++c) rgba[c] = texel[c];
}

// Phong pixels of one triangle, lit in batches by the lighting kernel; a surface draw's pixels
// carry their albedo and the tail's inputs (pixel/stages.hpp: carry), and finish the pixel
// program after lighting.
class PixelBatch {
 public:
  static constexpr int kCapacity = 64;
  explicit PixelBatch(lighting::SoaScratch& scratch) : scratch_(scratch) {}

  void add(std::size_t index, const Vec3& p, const Vec3& n) {
    occlusion_[count_] = 1.0f;
    metal_rough_[count_] = metal_rough_[kCapacity + count_] = 1.0f;
    push(index, p, n);
  }
  void add_surface(std::size_t index, const Vec3& p, const Vec3& n, const Color3& albedo, float occlusion, float metal,
                   float rough, const simd::Draw& d, const simd::Fog& fog, const stages::TailInputs<float>& in) {
    albedo_[count_] = albedo;
    occlusion_[count_] = occlusion;
    metal_rough_[count_] = metal, metal_rough_[kCapacity + count_] = rough;
    stages::carry(d, fog, in, carried_[count_]);
    push(index, p, n);
  }
  bool full() const { return count_ == kCapacity; }

  void flush(const lighting::PointShader& shader, const simd::Draw& d, const simd::Fog& fog, float alpha,
             TileBuffers& tile, RasterCounters& counters) {
    if (count_ == 0) return;
    const bool surface = pixel::runs_surface_stages(d.program);
    const bool separate = surface && d.separate_specular;
    if (count_ < kCapacity) {  // the roughness texels right after the metallic ones (shade_points' layout)
      std::copy_n(metal_rough_ + kCapacity, count_, metal_rough_ + count_);
    }
    shader.shade_points(static_cast<std::size_t>(count_), p_, n_, out_, scratch_, albedo_, separate ? spec_ : nullptr,
                        occlusion_, metal_rough_);
    for (int i = 0; i < count_; ++i) {
      const auto p = static_cast<std::size_t>(index_[i]);
      if (!surface) {
        tile.plane(0)[p] = out_[i].x();
        tile.plane(1)[p] = out_[i].y();
        tile.plane(2)[p] = out_[i].z();
        tile.plane(3)[p] = alpha;
        continue;
      }
      const float primary[3] = {out_[i].x(), out_[i].y(), out_[i].z()};
      const float secondary[3] = {spec_[i].x(), spec_[i].y(), spec_[i].z()};
      const float position[3] = {p_[i].x(), p_[i].y(), p_[i].z()}, normal[3] = {n_[i].x(), n_[i].y(), n_[i].z()};
      float c[4];
      stages::lit_surface_colour(d, fog, primary, secondary, position, normal, [&](int q) { return carried_[i][q]; }, alpha,
                                 level0, c);
      float dst[4] = {tile.plane(0)[p], tile.plane(1)[p], tile.plane(2)[p], tile.plane(3)[p]};
      stages::blend(d, c, dst);
      for (int ch = 0; ch < 4; ++ch) tile.plane(ch)[p] = dst[ch];
    }
    counters.shaded += static_cast<std::uint64_t>(count_);
    counters.light_pairs += static_cast<std::uint64_t>(count_) * shader.light_count();
    counters.skipped_pairs += static_cast<std::uint64_t>(count_) * shader.culled_lights();
    count_ = 0;
  }

 private:
  void push(std::size_t index, const Vec3& p, const Vec3& n) {
    index_[count_] = index;
    p_[count_] = p;
    n_[count_] = n;
    ++count_;
  }
  int count_ = 0;
  std::size_t index_[kCapacity];
  Vec3 p_[kCapacity], n_[kCapacity];
  Color3 out_[kCapacity], spec_[kCapacity], albedo_[kCapacity];
  float occlusion_[kCapacity];
  float metal_rough_[2 * kCapacity];  // metallic texels at [0, kCapacity), roughness at [kCapacity, 2 kCapacity)
  float carried_[kCapacity][simd::kMaxCarried];
  lighting::SoaScratch& scratch_;
};


// The Phong sink of the SIMD kernels: lights the gathered pixels with the object's shader.
struct PhongContext {
  const RasterJob* job;
  RasterCounters* counters;
  float* buffers;  // TileBuffers::phong
};

void shade_phong(void* context, std::uint32_t object, std::size_t count, std::size_t padded) {
  auto& c = *static_cast<PhongContext*>(context);
  const lighting::PointShader& shader = c.job->objects[object];
  float* f = c.buffers;
  const std::size_t cap = simd::kPhongCapacity;
  lighting::simd::Streams streams{f, f + cap, f + 2 * cap, f + 3 * cap, f + 4 * cap, f + 5 * cap, f + 6 * cap, f + 7 * cap,
                        f + 8 * cap, padded};
  streams.ar = f + 9 * cap, streams.ag = f + 10 * cap, streams.ab = f + 11 * cap;
  streams.sr = f + 12 * cap, streams.sg = f + 13 * cap, streams.sb = f + 14 * cap;
  streams.ao = f + 15 * cap;  // read when the object's lighting has occlusion
  streams.pm = f + 16 * cap, streams.pr = f + 17 * cap;  // read when it has a metallic-roughness map
  shader.shade_soa(streams, f + simd::kPhongStreams * cap, f + (simd::kPhongStreams + lighting::kMaxShadowedLights) * cap);
  c.counters->shaded += count;
  c.counters->light_pairs += count * shader.light_count();
  c.counters->skipped_pairs += count * shader.culled_lights();
}

void rasterize_tile_simd(const RasterJob& job, std::span<const std::uint32_t> bin, const TileRect& rect,
                         TileBuffers& tile, RasterCounters& counters) {
  PhongContext context{&job, &counters, tile.phong.data()};
  float* f = tile.phong.data();
  const std::size_t cap = simd::kPhongCapacity;
  simd::PhongSink sink{};
  float** slots[18] = {&sink.px, &sink.py, &sink.pz, &sink.nx, &sink.ny, &sink.nz, &sink.r,  &sink.g,  &sink.b,
                       &sink.ar, &sink.ag, &sink.ab, &sink.sr, &sink.sg, &sink.sb, &sink.ao, &sink.pm, &sink.pr};
  for (int k = 0; k < 18; ++k) *slots[k] = f + static_cast<std::size_t>(k) * cap;
  for (int k = 0; k < simd::kMaxCarried; ++k) sink.carry[k] = f + static_cast<std::size_t>(18 + k) * cap;
  sink.pixel = tile.phong_pixel.data();
  sink.samples = job.samples.count > 1 ? tile.phong_samples.data() : nullptr;
  sink.context = &context;
  sink.shade = shade_phong;
  simd::TileJob tj{job.shading,
                   job.ranges,
                   bin.data(),
                   bin.size(),
                   rect.x0,
                   rect.y0,
                   rect.x1,
                   rect.y1,
                   &sink,
                   job.draws,
                   job.fog};
  simd::TileCounters tc;
  simd::TileView tv = tile.view(job.clear_color, job.depth, nullptr, &job.samples);
  if (job.backdrop) {
    fill_backdrop(*job.backdrop, rect, tile, job.depth.far());
    tv.prefilled = true;
  }
  job.kernels->raster(tj, tv, tc);
  counters.tested += tc.tested;
  counters.filled += tc.filled;
}

}  // namespace

// One RGBA float pixel in an output format (8-bit channels as to_unorm8, or sRGB-encoded colour
// with `srgb`; floats as they are).
void store_pixel(const float* rgba, PixelFormat format, const SrgbTable* srgb, std::uint8_t* dst) {
  auto colour = [srgb](float v) { return srgb ? srgb_unorm8(*srgb, v) : to_unorm8(v); };
  switch (format) {
    case PixelFormat::rgba8:
      for (int c = 0; c < 3; ++c) dst[c] = colour(rgba[c]);
      dst[3] = to_unorm8(rgba[3]);
      break;
    case PixelFormat::bgra8:
      dst[0] = colour(rgba[2]);
      dst[1] = colour(rgba[1]);
      dst[2] = colour(rgba[0]);
      dst[3] = to_unorm8(rgba[3]);
      break;
    case PixelFormat::rgba32f: std::memcpy(dst, rgba, 16); break;
  }
}

void rasterize_tile(const RasterJob& job, std::span<const std::uint32_t> bin, const TileRect& rect,
                    TileBuffers& tile, lighting::SoaScratch& scratch, RasterCounters& counters) {
  if (job.kernels) {
    rasterize_tile_simd(job, bin, rect, tile, counters);
    return;
  }
  const int samples = job.samples.count;
  if (job.backdrop) {  // each pixel's clear value from the backdrop
    fill_backdrop(*job.backdrop, rect, tile, job.depth.far());
  } else {
    for (int s = 0; s < samples; ++s) {
      for (int y = 0; y < rect.y1 - rect.y0; ++y) {
        for (int x = 0; x < rect.x1 - rect.x0; ++x) {
          const std::size_t p = tile.index(x, y) + static_cast<std::size_t>(s) * tile.sample_stride();
          for (int c = 0; c < 4; ++c) tile.plane(c)[p] = job.clear_color[static_cast<std::size_t>(c)];
          tile.plane(4)[p] = job.depth.far();
        }
      }
    }
  }

  PixelBatch batch(scratch);
  for (const std::uint32_t entry : bin) {
    const ScreenTriangle& t = job.ranges[entry >> kRangeShift][entry & kIndexMask];
    const int x0 = std::max(t.min_px, rect.x0), x1 = std::min(t.max_px, rect.x1 - 1);
    const int y0 = std::max(t.min_py, rect.y0), y1 = std::min(t.max_py, rect.y1 - 1);
    if (x0 > x1 || y0 > y1) continue;

    const lighting::PointShader& shading = job.objects[t.object];
    const simd::Draw& d = job.draws[t.object];
    const VaryingLayout& layout = d.layout;
    const int colour_at = layout.at(Varying::front_color);
    const int position_at = layout.at(Varying::eye_position), normal_at = layout.at(Varying::normal);
    const int albedo_at = layout.at(Varying::albedo), uv_at = layout.at(Varying::uv);
    const simd::Fog& fog = *job.fog;
    // Attributes from the planes, as the SIMD kernels: a plane's value at the pixel centre in
    // double, rounded to float, over the interpolated 1/w.
    const double vx = double(t.x[0]) / kSubpixelOne, vy = double(t.y[0]) / kSubpixelOne;
    const float inv_area2 = static_cast<float>(1.0 / static_cast<double>(signed_area2(t)));
    // Each sample in turn (one: the pixel centre): coverage and depth at the sample, the pixel's
    // colour at its centre (GL's per-pixel shading), stored at the sample's index.
    for (int sample = 0; sample < samples; ++sample) {
    const std::size_t sample_offset = static_cast<std::size_t>(sample) * tile.sample_stride();
    for_each_covered_pixel(t, x0, y0, x1, y1, [&](int x, int y, std::int64_t e0, std::int64_t e1, std::int64_t e2) {
      ++counters.tested;
      const float l0 = static_cast<float>(e0) * inv_area2;
      const float l1 = static_cast<float>(e1) * inv_area2;
      const float l2 = static_cast<float>(e2) * inv_area2;
      float z = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
      z = z > job.depth.lo() ? (z < job.depth.far() ? z : job.depth.far()) : job.depth.lo();
      const std::size_t pixel = tile.index(x - rect.x0, y - rect.y0) + sample_offset;
      float* depth = tile.plane(4);
      if (!(z < depth[pixel])) return;  // depth test: LESS
      const double cx = x + 0.5 - vx, cy = y + 0.5 - vy;
      auto plane_at = [&](const Plane& q) { return static_cast<float>(q.at_v0 + q.dx * cx + q.dy * cy); };
      const float inv_sum = 1.0f / plane_at(t.plane[kPlaneInvW]);  // clip w: the eye-space depth
      auto interp = [&](int a) { return plane_at(t.plane[kPlaneAttr + a]) * inv_sum; };
      if (pixel::runs_surface_stages(d.program)) {
        // The surface program's stages (pixel/stages.hpp), one pixel at a time.
        float texel[4];
        const float* tex = nullptr;
        stages::Uv<float> uv{};
        if (uv_at >= 0) {
          const Plane& pw = t.plane[kPlaneInvW];
          const Plane& pu = t.plane[kPlaneAttr + uv_at];
          const Plane& pv = t.plane[kPlaneAttr + uv_at + 1];
          uv = stages::uv_from_planes(d, plane_at(pu), plane_at(pv), inv_sum, pu.dx, pu.dy, pv.dx, pv.dy, pw.dx, pw.dy);
        }
        // A map at the pixel's coordinates moved by (du, dv), with its LOD.
        auto sample_moved = [&uv](const texture::Sampler& sampler, float du, float dv, float (&out)[4]) {
          const float lambda = texture::lod_scalar(sampler, uv.dudx, uv.dvdx, uv.dudy, uv.dvdy);
          const auto value = texture::sample_scalar(sampler, uv.u + du, uv.v + dv, lambda);
          for (int c = 0; c < 4; ++c) out[c] = value[c];
        };
        auto sample_at = [&](const texture::Sampler& sampler, float (&out)[4]) { sample_moved(sampler, 0.0f, 0.0f, out); };
        if (d.texture && d.fixed_texels) {  // the 16-bit tier: the fixed-point sampler, byte / 255
          const float lambda = texture::lod_scalar(*d.texture, uv.dudx, uv.dvdx, uv.dudy, uv.dvdy);
          const std::uint32_t bytes = texture::sample_fixed_scalar(*d.texture, uv.u, uv.v, lambda);
          for (int c = 0; c < 4; ++c) texel[c] = static_cast<float>((bytes >> (8 * c)) & 0xffu) * (1.0f / 255.0f);
          tex = texel;
        } else if (d.texture) {
          sample_at(*d.texture, texel);
          tex = texel;
        }
        const float alpha = stages::fragment_alpha(d, t.alpha, tex);
        if (d.alpha_to_coverage && !stages::alpha_covers(alpha, sample, samples)) return;
        if (!(alpha >= d.alpha_cutoff)) return;  // the alpha test
        if (d.depth_write) depth[pixel] = z;
        ++counters.filled;
        auto to_phong = [&](const stages::TailInputs<float>& in) {
          const Color3 albedo = albedo_at >= 0 ? Color3(interp(albedo_at), interp(albedo_at + 1), interp(albedo_at + 2))
                                               : Color3(1.0f, 1.0f, 1.0f);
          float n[3];
          stages::pixel_normal(d, interp, t.bitangent_negative(), sample_moved, n);
          float metal = 1.0f, rough = 1.0f;
          stages::metal_rough<float>(d, sample_at, metal, rough);
          batch.add_surface(pixel, Vec3(interp(position_at), interp(position_at + 1), interp(position_at + 2)),
                            Vec3(n[0], n[1], n[2]), albedo, stages::occlusion<float>(d, sample_at), metal, rough, d, fog, in);
          if (batch.full()) batch.flush(shading, d, fog, t.alpha, tile, counters);
        };
        float c[4];
        if (!stages::surface_tail(d, fog, job.shading, t, interp, inv_sum, tex, t.alpha, sample_at, sample_moved, level0, to_phong, c)) {
          return;
        }
        float dst[4] = {tile.plane(0)[pixel], tile.plane(1)[pixel], tile.plane(2)[pixel], tile.plane(3)[pixel]};
        stages::blend(d, c, dst);
        for (int ch = 0; ch < 4; ++ch) tile.plane(ch)[pixel] = dst[ch];
        return;
      }
      depth[pixel] = z;
      ++counters.filled;
      auto put = [&](float r, float g, float b) {
        tile.plane(0)[pixel] = r;
        tile.plane(1)[pixel] = g;
        tile.plane(2)[pixel] = b;
        tile.plane(3)[pixel] = t.alpha;
      };
      if (job.shading == ShadingMode::flat) {
        put(t.flat_rgb[0], t.flat_rgb[1], t.flat_rgb[2]);
      } else if (job.shading == ShadingMode::gouraud) {
        put(interp(colour_at), interp(colour_at + 1), interp(colour_at + 2));
      } else {
        const int p = position_at, n = normal_at;
        batch.add(pixel, Vec3(interp(p), interp(p + 1), interp(p + 2)), Vec3(interp(n), interp(n + 1), interp(n + 2)));
        if (batch.full()) batch.flush(shading, d, fog, t.alpha, tile, counters);
      }
    }, job.samples.x[sample], job.samples.y[sample]);
    }
    batch.flush(shading, d, fog, t.alpha, tile, counters);
  }
}

namespace {

// Multisampling: every touched block's samples into its sample 0, which the resolve writes out:
// colour channels as their mean in linear float (summed in sample order, times 1/N, a power of
// two: the same bits on every path and ISA), depth as the nearest sample's (stored depth is
// smaller nearer in either depth format).
void average_samples(TileBuffers& tile, const TileRect& rect, int samples) {
  const std::size_t stride = tile.sample_stride();
  const float scale = 1.0f / static_cast<float>(samples);
  const int blocks_per_row = tile.size / simd::kBlock;
  const int nbx = (rect.x1 - rect.x0 + simd::kBlock - 1) / simd::kBlock, nby = (rect.y1 - rect.y0 + simd::kBlock - 1) / simd::kBlock;
  for (int by = 0; by < nby; ++by) {
    for (int bx = 0; bx < nbx; ++bx) {
      const int block = by * blocks_per_row + bx;
      if (!tile.touched[static_cast<std::size_t>(block)]) continue;
      const std::size_t base = static_cast<std::size_t>(block) * simd::kBlockPixels;
      // Sample by sample over the block's contiguous pixels (the compiler's vectors), each pixel's
      // sum in sample order.
      for (int c = 0; c < 4; ++c) {
        float* p = tile.plane(c) + base;
        for (int s = 1; s < samples; ++s) {
          const float* q = p + static_cast<std::size_t>(s) * stride;
          for (int i = 0; i < simd::kBlockPixels; ++i) p[i] += q[i];
        }
        for (int i = 0; i < simd::kBlockPixels; ++i) p[i] = p[i] * scale;
      }
      float* z = tile.plane(4) + base;
      for (int s = 1; s < samples; ++s) {
        const float* q = z + static_cast<std::size_t>(s) * stride;
        for (int i = 0; i < simd::kBlockPixels; ++i) z[i] = std::min(z[i], q[i]);
      }
    }
  }
}

}  // namespace

void resolve_tile(const RasterJob& job, TileBuffers& tile, const TileRect& rect, const ImageView& color,
                  const DepthView* depth) {
  // One resolve for both rasterizers: the scalar one fills every block of its tile, so they are
  // all marked touched and go through the sse2 kernel (every x86-64 CPU has it), which converts
  // as store_pixel does.
  const simd::Kernels* kernels = job.kernels ? job.kernels : simd_raster_kernels(Isa::sse2);
  if (!job.kernels) std::fill(tile.touched.begin(), tile.touched.end(), std::uint8_t{1});
  if (job.samples.count > 1) average_samples(tile, rect, job.samples.count);
  kernels->resolve(tile.view(job.clear_color, job.depth, job.srgb), rect.x0, rect.y0, rect.x1, rect.y1, color, depth);
}

void resolve_clear_tile(const std::array<float, 4>& clear_color, const SrgbTable* srgb, const TileRect& rect,
                        const ImageView& color, const DepthView* depth, float far_depth) {
  // One pixel in the output format, converted by the same code as resolve_tile.
  std::uint8_t pixel[16];
  const std::size_t bpp = bytes_per_pixel(color.format);
  store_pixel(clear_color.data(), color.format, srgb, pixel);
  const std::size_t row_bytes = static_cast<std::size_t>(rect.x1 - rect.x0) * bpp;
  const std::uint8_t* first_color = nullptr;
  const std::uint8_t* first_depth = nullptr;
  for (int y = rect.y0; y < rect.y1; ++y) {
    std::uint8_t* dst = io::row_bytes(color, y) + static_cast<std::size_t>(rect.x0) * bpp;
    if (first_color) {
      // Every row is the same as the first: streaming stores from the first 16-byte boundary
      // (the image is not read back by the frame, and a read for ownership would double the traffic).
      const std::size_t head = std::min(row_bytes, (16 - reinterpret_cast<std::uintptr_t>(dst) % 16) % 16);
      std::memcpy(dst, first_color, head);
      std::size_t i = head;
      for (; i + 16 <= row_bytes; i += 16) {
        _mm_stream_si128(reinterpret_cast<__m128i*>(dst + i), _mm_loadu_si128(reinterpret_cast<const __m128i*>(first_color + i)));
      }
      std::memcpy(dst + i, first_color + i, row_bytes - i);
    } else {
      if (bpp == 4) {
        for (int x = rect.x0; x < rect.x1; ++x) std::memcpy(dst + 4 * (x - rect.x0), pixel, 4);
      } else {
        for (int x = rect.x0; x < rect.x1; ++x) std::memcpy(dst + 16 * (x - rect.x0), pixel, 16);
      }
      first_color = dst;
    }
    if (depth) {
      std::uint8_t* d = io::row_bytes(*depth, y) + static_cast<std::size_t>(rect.x0) * sizeof(float);
      if (first_depth) {
        std::memcpy(d, first_depth, static_cast<std::size_t>(rect.x1 - rect.x0) * sizeof(float));
      } else {
        for (int x = rect.x0; x < rect.x1; ++x) std::memcpy(d + 4 * (x - rect.x0), &far_depth, 4);
        first_depth = d;
      }
    }
  }
  _mm_sfence();  // the streaming stores are visible before the tile's job is reported done
}

namespace {
float* depth_row(const DepthView& depth, int y) { return reinterpret_cast<float*>(io::row_bytes(depth, y)); }
}  // namespace

void resolve_depth_tile(const RasterJob& job, const TileBuffers& tile, const TileRect& rect, const DepthView& depth) {
  const int blocks_per_row = tile.size / simd::kBlock;
  const float* plane = tile.plane(4);
  for (int y = rect.y0; y < rect.y1; ++y) {
    float* out = depth_row(depth, y);
    const int ty = y - rect.y0;
    for (int x = rect.x0; x < rect.x1; x += simd::kBlock) {  // a block's row at a time
      const int tx = x - rect.x0, width = std::min(simd::kBlock, rect.x1 - x);
      const bool touched = !job.kernels || tile.touched[static_cast<std::size_t>((ty / simd::kBlock) * blocks_per_row + tx / simd::kBlock)];
      if (touched) {
        const float* in = plane + tile.index(tx, ty);
        for (int k = 0; k < width; ++k) out[x + k] = job.depth.output(in[k]);
      } else {
        std::fill(out + x, out + x + width, job.depth.output(job.depth.far()));
      }
    }
  }
}

void resolve_clear_depth(const TileRect& rect, const DepthView& depth) {
  for (int y = rect.y0; y < rect.y1; ++y) std::fill(depth_row(depth, y) + rect.x0, depth_row(depth, y) + rect.x1, 1.0f);
}

}  // namespace facet::tile
