// Internal: the SIMD tile rasterizer, a template on the xsimd architecture. Only the per-ISA files
// raster_simd_{sse2,avx2,avx512}.cpp include this header; each instantiates it once with its own
// flags, always with -ffp-contract=off so that every ISA does the same IEEE operations in the same
// order: images are then byte-identical across sse2, avx2 and avx512 (tests/raster_simd_test.cpp).
// Everything here is a template on Arch or sits in an unnamed namespace, so no inline function is
// shared with another ISA's object file (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
//
// Per triangle and tile:
//   1. Hierarchical test on 8x8 blocks with the exact 64-bit edge functions at the block corners:
//      a block outside an edge is skipped; edges the whole block is inside are not tested again.
//   2. Blocks on an edge test each pixel in 32-bit lanes, exactly: within a block
//        E(i, j) = E(block) + 256 (A i + B j)   (A, B: the edge's fixed-point deltas, |A|,|B| < 2^24)
//      so E >= 0  <=>  A i + B j + floor(E(block) / 256) >= 0, where |A i + B j| <= 7 (|A|+|B|) < 2^28
//      and, the block being on the edge, |E(block) / 256| <= 7 (|A|+|B|) as well: no overflow, and
//      the same pixels as the scalar rasterizer's int64 test (coverage is identical on every path).
//   3. Depth and attributes from screen-space planes (ScreenTriangle::plane): the value at the
//      block origin in double, rounded to float, plus (i dx + j dy) per lane in float; 1/w and
//      attribute/w planes, divided per pixel, give perspective-correct attributes.
#pragma once

#include <cstring>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "raster/raster_kernels.hpp"
#include "raster/surface_program.hpp"
#include "texture/sample_simd.hpp"

namespace facet::raster::simd {
namespace {

template <class Arch>
struct TileKernel {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using BF = xsimd::batch_bool<float, Arch>;
  using BI = xsimd::batch_bool<std::int32_t, Arch>;
  using U = xsimd::batch<std::uint32_t, Arch>;
  static constexpr int W = static_cast<int>(F::size);
  alignas(64) static constexpr std::uint32_t kLaneIndex[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  // For each mask of 8 lanes, the set lanes in order, then zeros: a permutation that compresses.
  struct Compress8 {
    alignas(32) std::int32_t lanes[256][8];
  };
  static constexpr Compress8 make_compress8() {
    Compress8 c{};
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int lane = 0; lane < 8; ++lane)
        if (m & (1 << lane)) c.lanes[m][k++] = lane;
    }
    return c;
  }
  static constexpr Compress8 kCompress8 = make_compress8();
  static constexpr int kBatches = kBlockPixels / W;
  static_assert(kBlockPixels % W == 0 && (W <= kBlock ? kBlock % W == 0 : W % kBlock == 0));

  // Lane q of a block (q = batch * W + lane) is pixel (q % 8, q / 8).
  struct Lanes {
    alignas(64) float fi[kBlockPixels], fj[kBlockPixels];
    alignas(64) std::int32_t ii[kBlockPixels], jj[kBlockPixels];
    alignas(64) std::int32_t bit0[16], bit1[16], bit2[16];  // batch 0 on sse2: masks of i's bits
  };
  static const Lanes& lanes() {
    static constexpr Lanes l = [] {
      Lanes r{};
      for (int q = 0; q < kBlockPixels; ++q) {
        r.fi[q] = static_cast<float>(q % kBlock), r.fj[q] = static_cast<float>(q / kBlock);
        r.ii[q] = q % kBlock, r.jj[q] = q / kBlock;
      }
      for (int q = 0; q < 16; ++q) {
        r.bit0[q] = (q % kBlock) & 1 ? -1 : 0;
        r.bit1[q] = (q % kBlock) & 2 ? -1 : 0;
        r.bit2[q] = (q % kBlock) & 4 ? -1 : 0;
      }
      return r;
    }();
    return l;
  }

  static int imin(int a, int b) { return a < b ? a : b; }
  static int imax(int a, int b) { return a > b ? a : b; }
  static std::int64_t lmin0(std::int64_t a) { return a < 0 ? a : 0; }
  static std::int64_t lmax0(std::int64_t a) { return a > 0 ? a : 0; }

  // Block-origin values and per-lane steps of one plane.
  struct PlaneEval {
    double at_v0, dxd, dyd;
    F dx, dy;
    void set(const Plane& p) {
      at_v0 = p.at_v0, dxd = p.dx, dyd = p.dy;
      dx = F(p.dx), dy = F(p.dy);
    }
    // Value at the block's first pixel centre, (cx, cy) relative to vertex 0.
    float origin(double cx, double cy) const { return static_cast<float>(at_v0 + dxd * cx + dyd * cy); }
    F at(float o, const F& fi, const F& fj) const { return F(o) + (fi * dx + fj * dy); }
  };

  // Gathers Phong pixels and lights them with one object's shader; entries are scattered back in
  // the order they were added, so when a pixel appears twice the later triangle wins (or, for a
  // blended draw, blends over the earlier one).
  struct PhongBatch {
    PhongSink* sink;
    const TileView* tile;
    const TileJob* job;
    int count = 0;
    std::uint32_t object = 0;
    float alpha = 1.0f;

    // Appends a batch's passing lanes (pixels at tile-buffer index `at` onwards) as vectors when
    // a whole batch fits before the capacity: stored as they are when every lane passed, else
    // compressed in a register (avx512 vcompressps, avx2 a permutation from kCompress8) and stored
    // whole; the lanes past the passing ones are overwritten by later entries or never read. Lane
    // order is kept, so the entries are those of the lane by lane copy, in the same order. False
    // (nothing appended): no room, or a partial batch on sse2; the caller copies lane by lane.
    // A compressing store straight to memory is microcoded on AMD Zen 4: it made the built-in
    // Phong frame 41 -> 58 ms.
    template <int Q>
    bool append(float* const (&dst)[Q], const F (&v)[Q], const BF& pass, std::size_t at) {
      if (count + W > kPhongCapacity) return false;
      const U pixel = U(static_cast<std::uint32_t>(at)) + U::load_aligned(kLaneIndex);
      int added = W;
      if (xsimd::all(pass)) {
        for (int q = 0; q < Q; ++q) v[q].store_unaligned(dst[q] + count);
        pixel.store_unaligned(sink->pixel + count);
      } else if constexpr (W == 16) {
        const __mmask16 m = static_cast<typename BF::register_type>(pass);
        for (int q = 0; q < Q; ++q) _mm512_storeu_ps(dst[q] + count, _mm512_maskz_compress_ps(m, v[q]));
        _mm512_storeu_si512(sink->pixel + count, _mm512_maskz_compress_epi32(m, pixel));
        added = __builtin_popcount(m);
      } else if constexpr (W == 8) {
        const int m = _mm256_movemask_ps(pass);
        const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompress8.lanes[m]));
        for (int q = 0; q < Q; ++q) _mm256_storeu_ps(dst[q] + count, _mm256_permutevar8x32_ps(v[q], order));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sink->pixel + count), _mm256_permutevar8x32_epi32(pixel, order));
        added = __builtin_popcount(static_cast<unsigned>(m));
      } else {
        return false;
      }
      count += added;
      if (count == kPhongCapacity) flush();
      return true;
    }

    void flush() {
      if (count == 0) return;
      int padded = (count + 15) / 16 * 16;
      PhongSink& s = *sink;
      float* const streams[] = {s.px, s.py, s.pz, s.nx, s.ny, s.nz, s.ar, s.ag, s.ab,
                                s.tr, s.tg, s.tb, s.ta, s.fog, s.er, s.eg, s.eb};
      for (float* f : streams) {
        for (int k = count; k < padded; ++k) f[k] = 0.0f;
      }
      s.shade(s.context, object, static_cast<std::size_t>(count), static_cast<std::size_t>(padded));
      const Draw& d = job->draws[object];
      if (!d.program) {
        for (int k = 0; k < count;) {
          if (run_at(k)) {  // W consecutive pixels: stored as vectors
            const std::uint32_t p = s.pixel[k];
            F::load_unaligned(s.r + k).store_unaligned(tile->plane[0] + p);
            F::load_unaligned(s.g + k).store_unaligned(tile->plane[1] + p);
            F::load_unaligned(s.b + k).store_unaligned(tile->plane[2] + p);
            F(alpha).store_unaligned(tile->plane[3] + p);
            k += W;
            continue;
          }
          const std::uint32_t p = s.pixel[k];
          tile->plane[0][p] = s.r[k];
          tile->plane[1][p] = s.g[k];
          tile->plane[2][p] = s.b[k];
          tile->plane[3][p] = alpha;
          ++k;
        }
        count = 0;
        return;
      }
      // The surface program's tail on the lit pixels, W at a time; the colour and alpha replace
      // r, g, b and ta. Then blend and store in entry order.
      // A textured draw's shader keeps the specular apart (separate specular); an untextured one sums it.
      const bool textured = d.texture != nullptr, secondary = textured;
      for (int k = 0; k < padded; k += W) {
        const F p[3] = {F::load_unaligned(s.r + k), F::load_unaligned(s.g + k), F::load_unaligned(s.b + k)};
        const F sec[3] = {F::load_unaligned(s.sr + k), F::load_unaligned(s.sg + k), F::load_unaligned(s.sb + k)};
        const F t[4] = {F::load_unaligned(s.tr + k), F::load_unaligned(s.tg + k), F::load_unaligned(s.tb + k),
                        F::load_unaligned(s.ta + k)};
        const F e[3] = {F::load_unaligned(s.er + k), F::load_unaligned(s.eg + k), F::load_unaligned(s.eb + k)};
        const F f = F::load_unaligned(s.fog + k);
        F c[4];
        surface::shade_fragment(d, *job->fog, p, F(alpha), textured ? t : nullptr, d.emission ? e : nullptr,
                                secondary ? sec : nullptr, &f, c);
        c[0].store_unaligned(s.r + k);
        c[1].store_unaligned(s.g + k);
        c[2].store_unaligned(s.b + k);
        c[3].store_unaligned(s.ta + k);
      }
      for (int k = 0; k < count;) {
        const std::uint32_t p = s.pixel[k];
        if (run_at(k)) {  // W consecutive pixels: blended as vectors (the same operations per pixel)
          const F c[4] = {F::load_unaligned(s.r + k), F::load_unaligned(s.g + k), F::load_unaligned(s.b + k),
                          F::load_unaligned(s.ta + k)};
          F dst[4];
          for (int ch = 0; ch < 4; ++ch) dst[ch] = F::load_unaligned(tile->plane[ch] + p);
          surface::blend(d, c, dst);
          for (int ch = 0; ch < 4; ++ch) dst[ch].store_unaligned(tile->plane[ch] + p);
          k += W;
          continue;
        }
        const float c[4] = {s.r[k], s.g[k], s.b[k], s.ta[k]};
        float dst[4] = {tile->plane[0][p], tile->plane[1][p], tile->plane[2][p], tile->plane[3][p]};
        surface::blend(d, c, dst);
        for (int ch = 0; ch < 4; ++ch) tile->plane[ch][p] = dst[ch];
        ++k;
      }
      count = 0;
    }
    // Whether entries k .. k + W - 1 exist and are the pixels pixel[k] .. pixel[k] + W - 1 (a whole
    // batch, append): distinct pixels, so storing them at once keeps the entry order's result.
    bool run_at(int k) const {
      if (k + W > count) return false;
      const U first(sink->pixel[k]);
      return xsimd::all(U::load_unaligned(sink->pixel + k) == first + U::load_aligned(kLaneIndex));
    }
  };

  // Marks every block of the tile untouched (the lazy clear; see TileView).
  static void clear(const TileJob& job, const TileView& tv) {
    const int nbx = (job.x1 - job.x0 + kBlock - 1) / kBlock, nby = (job.y1 - job.y0 + kBlock - 1) / kBlock;
    const int blocks_per_row = tv.size / kBlock;
    for (int by = 0; by < nby; ++by) {
      for (int bx = 0; bx < nbx; ++bx) tv.touched[by * blocks_per_row + bx] = 0;
    }
  }

  // First triangle to reach a block: fill it with the clear colour and far depth.
  static void touch(const TileView& tv, int block, std::size_t base) {
    if (tv.touched[block]) return;
    tv.touched[block] = 1;
    const F values[5] = {F(tv.clear[0]), F(tv.clear[1]), F(tv.clear[2]), F(tv.clear[3]), F(tv.depth_far)};
    for (int c = 0; c < 5; ++c) {
      for (int b = 0; b < kBatches; ++b) values[c].store_unaligned(tv.plane[c] + base + b * W);
    }
  }

  using Sampler = facet::texture::simd::SampleSimd<Arch>;

  // The surface program on one batch whose coverage and depth test gave `pass` (raster_kernels.hpp,
  // Draw): sample, alpha test, depth write, then the colour (Phong: gathered, finished at flush).
  // The batch's texture coordinates, scaled by the draw's uv_scale: perspective-correct uv and its
  // screen derivatives. cw: the interpolated clip w (1 / W').
  struct Uv {
    F u, v, dudx, dvdx, dudy, dvdy;
  };
  template <std::size_t N>
  static Uv uv_batch(const Draw& d, const PlaneEval (&attr)[N], const float (&attr_o)[N], const PlaneEval& w_plane,
                     const F& cw, const F& fi, const F& fj) {
    // u = U / W' with U = u/w and W' = 1/w affine on screen: du/dx = (dU/dx - u dW'/dx) / W'.
    const int uv = d.layout.at(Varying::uv);
    const F u = attr[uv].at(attr_o[uv], fi, fj) * cw, v = attr[uv + 1].at(attr_o[uv + 1], fi, fj) * cw;
    const F dudx = (attr[uv].dx - u * w_plane.dx) * cw, dudy = (attr[uv].dy - u * w_plane.dy) * cw;
    const F dvdx = (attr[uv + 1].dx - v * w_plane.dx) * cw, dvdy = (attr[uv + 1].dy - v * w_plane.dy) * cw;
    const F su(d.uv_scale[0]), sv(d.uv_scale[1]);
    return {su * u, sv * v, su * dudx, sv * dvdx, su * dudy, sv * dvdy};
  }
  // One texture at those coordinates (RGBA in tex): the LOD, the sample.
  static void sample_batch(const texture::Sampler& sampler, const Uv& c, F (&tex)[4]) {
    const F lambda = Sampler::lod(sampler, c.dudx, c.dvdx, c.dudy, c.dvdy);
    Sampler::sample(sampler, c.u, c.v, lambda, tex);
  }
  // The emission the draw adds after its texture environment (Draw::emission).
  static void emission_batch(const Draw& d, const Uv* c, F (&e)[3]) {
    if (d.emission_texture) {
      F t[4];
      sample_batch(*d.emission_texture, *c, t);
      for (int k = 0; k < 3; ++k) e[k] = F(d.emission_rgb[k]) * t[k];
    } else {
      for (int k = 0; k < 3; ++k) e[k] = F(d.emission_rgb[k]);
    }
  }

  // P batches of the same triangle and block (1 or 2: the sampler's interleaving, sample_simd.hpp),
  // each with its pixel coordinates (fi, fj), depth and passing lanes, at plane offset at[p]: the
  // texture sampled for all of them at once (with the triangle's level guess), then each batch's
  // tail in order. The same operations on each batch as on one, so the same bits.
  template <int P, std::size_t N>
  static void surface_batches(const TileJob& job, const Draw& d, const ScreenTriangle& t, const PlaneEval (&attr)[N],
                              const float (&attr_o)[N], const PlaneEval& w_plane, float w_o, const F (&fi)[P],
                              const F (&fj)[P], const F (&z)[P], const BF (&pass)[P], float* const (&planes)[5],
                              const std::size_t (&at)[P], PhongBatch& phong, int& level_guess, I& filled) {
    F cw[P], tex[P][4];
    Uv uv[P]{};  // zeros where the layout has no uv
    for (int p = 0; p < P; ++p) {
      cw[p] = F(1.0f) / w_plane.at(w_o, fi[p], fj[p]);  // clip w: the eye-space depth
      if (d.layout.has(Varying::uv)) uv[p] = uv_batch(d, attr, attr_o, w_plane, cw[p], fi[p], fj[p]);
    }
    if (d.texture) {
      F u[P], v[P], lambda[P];
      for (int p = 0; p < P; ++p) {
        u[p] = uv[p].u, v[p] = uv[p].v;
        lambda[p] = Sampler::lod(*d.texture, uv[p].dudx, uv[p].dvdx, uv[p].dudy, uv[p].dvdy);
      }
      Sampler::template sample<P>(*d.texture, u, v, lambda, tex, &level_guess);
    }
    for (int p = 0; p < P; ++p) {
      surface_tail(job, d, t, attr, attr_o, cw[p], fi[p], fj[p], z[p], pass[p], planes, at[p], phong, filled,
                   d.texture ? tex[p] : nullptr, uv[p]);
    }
  }
  // One batch of an untextured draw (an emission texture is sampled in the tail): inlined into
  // its own instantiation of triangle() (Mode 4), apart from the textured one (Mode 3), where
  // inlining it slowed the specialised program (avx2 textured fill 307 -> 330 ms); out of line,
  // a call per batch cost the blended fill about a quarter (avx512 73 -> 56 ms inlined).
  template <std::size_t N>
  [[gnu::always_inline]] inline static void surface_batch(const TileJob& job, const Draw& d, const ScreenTriangle& t,
                                                          const PlaneEval (&attr)[N], const float (&attr_o)[N],
                                                          const PlaneEval& w_plane, float w_o, const F& fi,
                                                          const F& fj, const F& z, BF pass, float* const (&planes)[5],
                                                          std::size_t at, PhongBatch& phong, I& filled) {
    const F cw = F(1.0f) / w_plane.at(w_o, fi, fj);
    Uv uv;
    if (d.layout.has(Varying::uv)) uv = uv_batch(d, attr, attr_o, w_plane, cw, fi, fj);
    surface_tail(job, d, t, attr, attr_o, cw, fi, fj, z, pass, planes, at, phong, filled, nullptr, uv);
  }
  // One batch's program after its texture sample (texel: null when the draw has no texture).
  template <std::size_t N>
  [[gnu::always_inline]] inline static void surface_tail(const TileJob& job, const Draw& d, const ScreenTriangle& t,
                                                         const PlaneEval (&attr)[N], const float (&attr_o)[N],
                                                         const F& cw, const F& fi, const F& fj, const F& z, BF pass,
                                                         float* const (&planes)[5], std::size_t at, PhongBatch& phong,
                                                         I& filled, const F* texel, const Uv& uv) {
    auto value = [&](int a) { return attr[a].at(attr_o[a], fi, fj) * cw; };
    const F alpha(t.alpha);
    pass = pass & (surface::fragment_alpha(d, alpha, texel) >= F(d.alpha_cutoff));  // the alpha test
    if (!xsimd::any(pass)) return;
    filled += xsimd::select(xsimd::bool_cast(pass), I(1), I(0));
    float* depth = planes[4] + at;
    if (d.depth_write) xsimd::select(pass, z, F::load_unaligned(depth)).store_unaligned(depth);
    const F f = job.fog->mode != FogMode::none ? surface::fog_factor(*job.fog, cw) : F(1.0f);
    F emitted[3];
    if (d.emission) emission_batch(d, &uv, emitted);
    if (job.shading == ShadingMode::phong) {  // light at flush
      F v[17];
      const int position = d.layout.at(Varying::eye_position), normal = d.layout.at(Varying::normal);
      const int albedo = d.layout.at(Varying::albedo);
      for (int c = 0; c < 3; ++c) {
        v[c] = value(position + c);
        v[3 + c] = value(normal + c);
        v[6 + c] = albedo >= 0 ? value(albedo + c) : F(1.0f);
      }
      for (int c = 0; c < 4; ++c) v[9 + c] = texel ? texel[c] : F(1.0f);
      v[13] = f;
      for (int c = 0; c < 3; ++c) v[14 + c] = d.emission ? emitted[c] : F(0.0f);
      PhongSink& s = *phong.sink;
      float* const dst[17] = {s.px, s.py, s.pz, s.nx, s.ny, s.nz, s.ar, s.ag, s.ab,
                              s.tr, s.tg, s.tb, s.ta, s.fog, s.er, s.eg, s.eb};
      if (phong.append(dst, v, pass, at)) return;
      alignas(64) float values[17][W];
      alignas(64) float mask[W];
      for (int q = 0; q < 17; ++q) v[q].store_aligned(values[q]);
      xsimd::select(pass, F(1.0f), F(0.0f)).store_aligned(mask);
      for (int lane = 0; lane < W; ++lane) {
        if (mask[lane] == 0.0f) continue;
        const int k = phong.count++;
        for (int q = 0; q < 17; ++q) dst[q][k] = values[q][lane];
        s.pixel[k] = static_cast<std::uint32_t>(at + static_cast<std::size_t>(lane));
        if (phong.count == kPhongCapacity) phong.flush();
      }
      return;
    }
    F p[3], sec[3];
    const F* secondary = nullptr;
    if (job.shading == ShadingMode::flat) {
      for (int c = 0; c < 3; ++c) p[c] = F(t.flat_rgb[c]), sec[c] = F(t.flat_secondary[c]);
      if (texel) secondary = sec;
    } else {
      const int colour = d.layout.at(Varying::front_color), second = d.layout.at(Varying::front_secondary);
      for (int c = 0; c < 3; ++c) p[c] = value(colour + c);
      if (second >= 0) {
        for (int c = 0; c < 3; ++c) sec[c] = value(second + c);
        secondary = sec;
      }
    }
    F c[4];
    surface::shade_fragment(d, *job.fog, p, alpha, texel, d.emission ? emitted : nullptr, secondary, &f, c);
    F old[4], out[4];
    for (int ch = 0; ch < 4; ++ch) out[ch] = old[ch] = F::load_unaligned(planes[ch] + at);
    surface::blend(d, c, out);
    for (int ch = 0; ch < 4; ++ch) xsimd::select(pass, out[ch], old[ch]).store_unaligned(planes[ch] + at);
  }

  // The surface program specialised for its commonest textured case: Gouraud, a texture under
  // GL_MODULATE with the specular added after it, no emission after it, fog or none, opaque, no
  // alpha test (cutoff <= 0 and the fragment's alpha is never NaN). The same operations in the
  // same order as surface_tail with shade_fragment and blend, so the same bits, without the
  // branches on the draw's settings.
  static bool modulate_fast(const TileJob& job, const Draw& d) {
    return d.texture && job.shading == ShadingMode::gouraud && d.texture_env == TextureMode::modulate && !d.emission &&
           d.blend == BlendMode::opaque &&
           d.clamp && d.alpha_cutoff <= 0.0f && d.layout.at(Varying::front_secondary) >= 0;
  }
  // P batches of the same triangle (1 or 2: the sampler's interleaving, sample_simd.hpp), each
  // with its pixel coordinates (fi, fj), depth and passing lanes, at plane offset at[p].
  template <int P, bool Fogged, std::size_t N>
  static void modulate_batch(const Fog& fog, const Draw& d, const ScreenTriangle& t, const PlaneEval (&attr)[N],
                             const float (&attr_o)[N], const PlaneEval& w_plane, float w_o, const F (&fi)[P],
                             const F (&fj)[P], const F (&z)[P], const BF (&pass)[P], float* const (&planes)[5],
                             const std::size_t (&at)[P], int& level_guess, I& filled) {
    F cw[P], u[P], v[P], lambda[P], tex[P][4];
    for (int p = 0; p < P; ++p) {
      cw[p] = F(1.0f) / w_plane.at(w_o, fi[p], fj[p]);
      const Uv c = uv_batch(d, attr, attr_o, w_plane, cw[p], fi[p], fj[p]);
      u[p] = c.u, v[p] = c.v;
      lambda[p] = Sampler::lod(*d.texture, c.dudx, c.dvdx, c.dudy, c.dvdy);
    }
    if constexpr (W < 16 && !Fogged) {
      Sampler::template sample_inline<P>(*d.texture, u, v, lambda, tex, &level_guess);
    } else {
      Sampler::template sample<P>(*d.texture, u, v, lambda, tex, &level_guess);
    }
    const int colour = d.layout.at(Varying::front_color), second = d.layout.at(Varying::front_secondary);
    for (int p = 0; p < P; ++p) {
      auto value = [&](int a) { return attr[a].at(attr_o[a], fi[p], fj[p]) * cw[p]; };
      filled += xsimd::select(xsimd::bool_cast(pass[p]), I(1), I(0));
      const bool all = xsimd::all(pass[p]);
      auto put = [&](int c, const F& x) {
        float* dst = planes[c] + at[p];
        (all ? x : xsimd::select(pass[p], x, F::load_unaligned(dst))).store_unaligned(dst);
      };
      if (d.depth_write) put(4, z[p]);
      if constexpr (!Fogged) {
        for (int c = 0; c < 3; ++c) put(c, surface::saturate(value(colour + c) * tex[p][c] + value(second + c)));
      } else {
        const F f = surface::fog_factor(fog, cw[p]);
        for (int c = 0; c < 3; ++c) {
          const F x = surface::saturate(value(colour + c) * tex[p][c] + value(second + c));
          put(c, f * x + (F(1.0f) - f) * F(fog.color[c]));
        }
      }
      put(3, surface::saturate(F(t.alpha) * tex[p][3]));
    }
  }

  static constexpr int kHold = W >= 16 ? 2 : 4;  // 2 x 16 lanes, 4 x 8 or 4 x 4 (measured best)
  // P held batches of a textured draw: the specialised program (kModulate, kModulateFog) or the
  // general one (kGeneral). The last two run out of line (other_held), so that triangle() and the
  // specialised program without fog compile as they did before them: inlined, they slowed that
  // program (avx512 textured fill 247 -> 265 ms, alternated runs).
  enum Program { kGeneral, kModulate, kModulateFog };
  template <int P, std::size_t N>
  [[gnu::noinline]] static void other_held(Program program, const TileJob& job, const Draw& d, const ScreenTriangle& t,
                                           const PlaneEval (&attr)[N], const float (&attr_o)[N],
                                           const PlaneEval& w_plane, float w_o, const F* fi, const F* fj, const F* z,
                                           const BF* pass, float* const (&planes)[5], const std::size_t* at,
                                           PhongBatch& phong, int& level_guess, I& filled) {
    F a[P], b[P], c[P];
    BF m[P];
    std::size_t o[P];
    for (int p = 0; p < P; ++p) a[p] = fi[p], b[p] = fj[p], c[p] = z[p], m[p] = pass[p], o[p] = at[p];
    if (program == kModulateFog) {
      modulate_batch<P, true>(*job.fog, d, t, attr, attr_o, w_plane, w_o, a, b, c, m, planes, o, level_guess, filled);
    } else {
      surface_batches<P>(job, d, t, attr, attr_o, w_plane, w_o, a, b, c, m, planes, o, phong, level_guess, filled);
    }
  }
  // The last 1 .. kHold - 1 held batches of a block.
  template <std::size_t N>
  static void held_rest(Program program, const TileJob& job, const Draw& d, const ScreenTriangle& t,
                        const PlaneEval (&attr)[N], const float (&attr_o)[N], const PlaneEval& w_plane, float w_o,
                        int held, const F* fi, const F* fj, const F* z, const BF* pass, float* const (&planes)[5],
                        const std::size_t* at, PhongBatch& phong, int& level_guess, I& filled) {
    auto run = [&](auto count) {
      constexpr int P = decltype(count)::value;
      if (program != kModulate) {
        other_held<P>(program, job, d, t, attr, attr_o, w_plane, w_o, fi, fj, z, pass, planes, at, phong, level_guess,
                      filled);
        return;
      }
      F a[P], b[P], c[P];
      BF m[P];
      std::size_t o[P];
      for (int p = 0; p < P; ++p) a[p] = fi[p], b[p] = fj[p], c[p] = z[p], m[p] = pass[p], o[p] = at[p];
      modulate_batch<P, false>(*job.fog, d, t, attr, attr_o, w_plane, w_o, a, b, c, m, planes, o, level_guess, filled);
    };
    if (held == 1) run(std::integral_constant<int, 1>{});
    if constexpr (kHold > 2) {
      if (held == 2) run(std::integral_constant<int, 2>{});
    }
    if constexpr (kHold > 3) {
      if (held == 3) run(std::integral_constant<int, 3>{});
    }
  }

  // Counters and plane pointers are locals: xsimd registers are may_alias vector types, so
  // accumulating into a reference (or reading pointers through one) after every pixel store would
  // force a store-to-load round trip per batch. Measured on 16 full-screen Gouraud layers at
  // 1080p, avx2, 1 thread (BM_Fill): 40.1 ms with reference accumulators, 35.2 ms with locals; then
  // 33.0 ms counting whole batches as scalars, 26.4 ms with a separate instantiation for blocks that
  // are fully covered (no per-batch coverage work): 2.43 G pixels/s on 2 threads.
  template <int Mode>
  static void triangle(const TileJob& job, const TileView& tv, const ScreenTriangle& t, const int (&plane_of)[6],
                       PhongBatch& phong, TileCounters& counters) {
    I tested(0), filled(0);                 // per lane, batches partly covered or partly passing
    std::uint64_t whole_tested = 0, whole_filled = 0;  // whole batches
    float* const planes[5] = {tv.plane[0], tv.plane[1], tv.plane[2], tv.plane[3], tv.plane[4]};
    const int x0 = imax(t.min_px, job.x0), x1 = imin(t.max_px, job.x1 - 1);
    const int y0 = imax(t.min_py, job.y0), y1 = imin(t.max_py, job.y1 - 1);
    if (x0 > x1 || y0 > y1) return;
    const int bx0 = (x0 - job.x0) / kBlock, bx1 = (x1 - job.x0) / kBlock;
    const int by0 = (y0 - job.y0) / kBlock, by1 = (y1 - job.y0) / kBlock;
    const int rect_w = job.x1 - job.x0, rect_h = job.y1 - job.y0;
    const int blocks_per_row = tv.size / kBlock;
    const Lanes& L = lanes();
    int level_guess = -1;  // the trilinear level the last batches read (SampleSimd::sample)

    // Edges: 64-bit values at the first block's first pixel centre (biased by the top-left rule),
    // steps between blocks, and the corner offsets that bound a block's values.
    std::int64_t e_row[3], step_bx[3], step_by[3], lo[3], hi[3];
    std::int32_t a32[3], b32[3];
    I lane_ab[3];  // A i + B j for the lanes of batch 0
    {
      const std::int64_t px = std::int64_t(job.x0 + bx0 * kBlock) * kSubpixelOne + kPixelCentre;
      const std::int64_t py = std::int64_t(job.y0 + by0 * kBlock) * kSubpixelOne + kPixelCentre;
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const std::int64_t A = -(std::int64_t(t.y[b]) - t.y[a]);
        const std::int64_t B = std::int64_t(t.x[b]) - t.x[a];
        e_row[k] = B * (py - t.y[a]) + A * (px - t.x[a]) + t.bias[k];
        const std::int64_t sa = A * kSubpixelOne, sb = B * kSubpixelOne;
        step_bx[k] = kBlock * sa;
        step_by[k] = kBlock * sb;
        lo[k] = lmin0((kBlock - 1) * sa) + lmin0((kBlock - 1) * sb);
        hi[k] = lmax0((kBlock - 1) * sa) + lmax0((kBlock - 1) * sb);
        a32[k] = static_cast<std::int32_t>(A);
        b32[k] = static_cast<std::int32_t>(B);
        // A i + B j, |A i| < 2^27: the 32-bit multiply on avx2 and avx512 (avx2's batch 0 is row 0,
        // j = 0); on sse2, which has none, A i from i's bits.
        if constexpr (W == 16) {
          lane_ab[k] = I(_mm512_add_epi32(_mm512_mullo_epi32(I(a32[k]), I::load_aligned(L.ii)),
                                          _mm512_mullo_epi32(I(b32[k]), I::load_aligned(L.jj))));
        } else if constexpr (W == 8) {
          lane_ab[k] = I(_mm256_mullo_epi32(I(a32[k]), I::load_aligned(L.ii)));
        } else {
          lane_ab[k] = (I(a32[k]) & I::load_aligned(L.bit0)) + (I(a32[k] * 2) & I::load_aligned(L.bit1)) +
                       (I(a32[k] * 4) & I::load_aligned(L.bit2));
        }
      }
    }

    // Planes: Gouraud's colour, or Phong's position then normal (where the draw's layout put
    // them); the surface program (Mode 3 with a texture, 4 without) evaluates every varying of
    // its layout, in layout order.
    constexpr bool kSurface = Mode >= 3;
    constexpr int kAttributes = kSurface ? geometry::kMaxAttributes : Mode == 2 ? 6 : 3;
    const Draw& d = job.draws[t.object];
    const int attributes = kSurface ? d.layout.raster : kAttributes;
    PlaneEval z_plane, w_plane, attr[kAttributes];
    z_plane.set(t.plane[kPlaneZ]);
    [[maybe_unused]] const Program program =
        Mode == 3 && modulate_fast(job, d) ? (job.fog->mode == FogMode::none ? kModulate : kModulateFog) : kGeneral;
    if constexpr (kSurface) {
      w_plane.set(t.plane[kPlaneInvW]);
      for (int a = 0; a < attributes; ++a) attr[a].set(t.plane[kPlaneAttr + a]);
    } else if constexpr (Mode != 0) {
      w_plane.set(t.plane[kPlaneInvW]);
      for (int a = 0; a < kAttributes; ++a) attr[a].set(t.plane[kPlaneAttr + plane_of[a]]);
    }
    const double vx = double(t.x[0]) / kSubpixelOne, vy = double(t.y[0]) / kSubpixelOne;
    const F flat[4] = {F(t.flat_rgb[0]), F(t.flat_rgb[1]), F(t.flat_rgb[2]), F(t.alpha)};
    const F alpha(t.alpha);

    for (int by = by0; by <= by1; ++by) {
      std::int64_t e[3] = {e_row[0], e_row[1], e_row[2]};
      for (int bx = bx0; bx <= bx1; ++bx, e[0] += step_bx[0], e[1] += step_bx[1], e[2] += step_bx[2]) {
        if (e[0] + hi[0] < 0 || e[1] + hi[1] < 0 || e[2] + hi[2] < 0) continue;  // outside an edge
        // Edges the block straddles, with their per-block lane values A i + B j + floor(E / 256).
        int partial = 0;
        I edge_base[3] = {I(0), I(0), I(0)};
        for (int k = 0; k < 3; ++k) {
          if (e[k] + lo[k] >= 0) continue;  // the whole block is inside this edge
          partial |= 1 << k;
          edge_base[k] = lane_ab[k] + I(static_cast<std::int32_t>(e[k] >> kSubpixelBits));
        }
        const int ox = bx * kBlock, oy = by * kBlock;  // block origin in the tile
        const bool clipped = ox + kBlock > rect_w || oy + kBlock > rect_h;
        const int block = by * blocks_per_row + bx;
        const std::size_t base = static_cast<std::size_t>(block) * kBlockPixels;
        touch(tv, block, base);
        const double cx = (job.x0 + ox) + 0.5 - vx, cy = (job.y0 + oy) + 0.5 - vy;
        const float z_o = z_plane.origin(cx, cy);
        float w_o = 0.0f, attr_o[kAttributes] = {};
        if constexpr (Mode != 0) {
          w_o = w_plane.origin(cx, cy);
          for (int a = 0; a < attributes; ++a) attr_o[a] = attr[a].origin(cx, cy);
        }

        // One batch of W pixels; Full: the block is inside every edge and the tile's rectangle, so
        // coverage is all lanes (a separate instantiation: no per-batch coverage work or branches).
        int held = 0;  // a textured draw's batches held for a group
        F held_fi[kHold], held_fj[kHold], held_z[kHold];
        BF held_pass[kHold];
        std::size_t held_at[kHold];
        auto shade_batch = [&](auto full_tag, int b) {
          constexpr bool kFull = decltype(full_tag)::value;
          BI cover_i(true);
          if constexpr (!kFull) {
            const int i0 = (b * W) % kBlock, j0 = (b * W) / kBlock;  // first lane's pixel in the block
            if (partial) {
              I acc(0);
              for (int k = 0; k < 3; ++k) {
                if (partial & (1 << k)) acc = acc | (edge_base[k] + I(a32[k] * i0 + b32[k] * j0));
              }
              cover_i = acc >= I(0);
            }
            if (clipped) {
              cover_i = cover_i & (I::load_aligned(L.ii + b * W) < I(rect_w - ox)) &
                        (I::load_aligned(L.jj + b * W) < I(rect_h - oy));
            }
            if (!xsimd::any(cover_i)) return;
          }
          const F fi = F::load_aligned(L.fi + b * W), fj = F::load_aligned(L.fj + b * W);
          float* depth = planes[4] + base + b * W;
          F z = z_plane.at(z_o, fi, fj);
          z = xsimd::select(z > F(tv.depth_lo), xsimd::min(z, F(tv.depth_far)), F(tv.depth_lo));  // NaN -> lo, as the scalar path
          const F old_z = F::load_unaligned(depth);
          BF pass = z < old_z;
          if constexpr (kFull) {
            whole_tested += W;
          } else {
            pass = pass & xsimd::bool_cast(cover_i);
            tested += xsimd::select(cover_i, I(1), I(0));
          }
          if (!xsimd::any(pass)) return;
          if constexpr (Mode == 3) {  // held until kHold batches of the block pass, then run together
            held_fi[held] = fi, held_fj[held] = fj, held_z[held] = z, held_pass[held] = pass;
            held_at[held] = base + static_cast<std::size_t>(b * W);
            if (++held == kHold) {
              if (program == kModulate) {
                modulate_batch<kHold, false>(*job.fog, d, t, attr, attr_o, w_plane, w_o, held_fi, held_fj, held_z,
                                             held_pass, planes, held_at, level_guess, filled);
              } else {
                other_held<kHold>(program, job, d, t, attr, attr_o, w_plane, w_o, held_fi, held_fj, held_z, held_pass,
                                  planes, held_at, phong, level_guess, filled);
              }
              held = 0;
            }
            return;
          } else if constexpr (Mode == 4) {
            surface_batch(job, d, t, attr, attr_o, w_plane, w_o, fi, fj, z, pass, planes, base + b * W, phong, filled);
            return;
          }
          const bool all = xsimd::all(pass);
          if (all) {
            whole_filled += W;
          } else {
            filled += xsimd::select(xsimd::bool_cast(pass), I(1), I(0));
          }
          auto put = [&](int c, const F& v) {
            float* dst = planes[c] + base + b * W;
            (all ? v : xsimd::select(pass, v, F::load_unaligned(dst))).store_unaligned(dst);
          };
          put(4, z);
          if constexpr (Mode == 0) {
            for (int c = 0; c < 4; ++c) put(c, flat[c]);
          } else {
            const F inv_w = F(1.0f) / w_plane.at(w_o, fi, fj);
            if constexpr (Mode == 1) {
              for (int c = 0; c < 3; ++c) put(c, attr[c].at(attr_o[c], fi, fj) * inv_w);
              put(3, alpha);
            } else {
              F v[6];
              for (int a = 0; a < 6; ++a) v[a] = attr[a].at(attr_o[a], fi, fj) * inv_w;
              PhongSink& s = *phong.sink;
              float* const dst[6] = {s.px, s.py, s.pz, s.nx, s.ny, s.nz};
              const std::size_t at = base + static_cast<std::size_t>(b * W);
              if (phong.append(dst, v, pass, at)) return;
              alignas(64) float values[6][W];
              alignas(64) float mask[W];
              for (int a = 0; a < 6; ++a) v[a].store_aligned(values[a]);
              xsimd::select(pass, F(1.0f), F(0.0f)).store_aligned(mask);
              for (int lane = 0; lane < W; ++lane) {
                if (mask[lane] == 0.0f) continue;
                const int k = phong.count++;
                s.px[k] = values[0][lane], s.py[k] = values[1][lane], s.pz[k] = values[2][lane];
                s.nx[k] = values[3][lane], s.ny[k] = values[4][lane], s.nz[k] = values[5][lane];
                s.pixel[k] = static_cast<std::uint32_t>(base + static_cast<std::size_t>(b * W + lane));
                if (phong.count == kPhongCapacity) phong.flush();
              }
            }
          }
        };
        if (!partial && !clipped) {
          for (int b = 0; b < kBatches; ++b) shade_batch(std::true_type{}, b);
        } else {
          // Only the batches that meet the triangle's bounds: a small triangle touches a few rows
          // of a block (bunny at 1080p: 10 pixels a triangle), the other batches are not worked.
          const int r0 = imax(0, y0 - job.y0 - oy), r1 = imin(kBlock - 1, y1 - job.y0 - oy);
          const int c0 = imax(0, x0 - job.x0 - ox), c1 = imin(kBlock - 1, x1 - job.x0 - ox);
          for (int b = (r0 * kBlock) / W; b <= (r1 * kBlock + kBlock - 1) / W; ++b) {
            if constexpr (W < kBlock) {  // a batch is part of a row: skip the parts outside the columns
              const int first = (b * W) % kBlock;
              if (first > c1 || first + W - 1 < c0) continue;
            }
            shade_batch(std::false_type{}, b);
          }
        }
        if constexpr (Mode == 3) {
          if (held > 0) {
            held_rest(program, job, d, t, attr, attr_o, w_plane, w_o, held, held_fi, held_fj, held_z, held_pass, planes,
                      held_at, phong, level_guess, filled);
          }
        }
      }
      for (int k = 0; k < 3; ++k) e_row[k] += step_by[k];
    }
    // Lane counters cannot overflow within one triangle and tile (< 2^16 pixels).
    counters.tested += static_cast<std::uint32_t>(xsimd::hadd(tested)) + whole_tested;
    counters.filled += static_cast<std::uint32_t>(xsimd::hadd(filled)) + whole_filled;
  }

  static void raster(const TileJob& job, const TileView& tv, TileCounters& counters) {
    clear(job, tv);
    PhongBatch phong{job.phong, &tv, &job};
    // Attribute plane k of the plain kernels: colour components (Gouraud), or position then normal
    // (Phong), from the draw's layout (recomputed when the draw changes).
    int plane_of[6] = {};
    std::uint32_t layout_of = ~0u;
    for (std::size_t n = 0; n < job.bin_size; ++n) {
      if (n + 2 < job.bin_size) {  // the triangle after next: set-up wrote it long ago, so it is not in cache
        const std::uint32_t ahead = job.bin[n + 2];
        const auto* p = reinterpret_cast<const char*>(&job.ranges[ahead >> kRangeShift][ahead & kIndexMask]);
        __builtin_prefetch(p);  // a plain Gouraud triangle's kernel data: its first two lines (triangle_setup.hpp)
        __builtin_prefetch(p + 64);
        if (job.shading != ShadingMode::gouraud) {  // flat colour, Phong's six attributes
          __builtin_prefetch(p + 128);
          __builtin_prefetch(p + 192);
        }
      }
      const std::uint32_t entry = job.bin[n];
      const ScreenTriangle& t = job.ranges[entry >> kRangeShift][entry & kIndexMask];
      const Draw& d = job.draws[t.object];
      if (t.object != layout_of) {
        layout_of = t.object;
        const std::int8_t* at = d.layout.offset;
        const int colour = at[static_cast<int>(Varying::front_color)];
        const int position = at[static_cast<int>(Varying::eye_position)], normal = at[static_cast<int>(Varying::normal)];
        for (int c = 0; c < 3; ++c) {
          plane_of[c] = job.shading == ShadingMode::phong ? position + c : colour + c;
          plane_of[3 + c] = job.shading == ShadingMode::phong ? normal + c : 0;
        }
      }
      if (job.shading == ShadingMode::phong) {
        if (phong.count > 0 && (t.object != phong.object || t.alpha != phong.alpha)) phong.flush();
        phong.object = t.object;
        phong.alpha = t.alpha;
      }
      if (d.program) {  // the surface program: a textured draw's batches are held and sampled together
        if (d.texture) {
          triangle<3>(job, tv, t, plane_of, phong, counters);
        } else {
          triangle<4>(job, tv, t, plane_of, phong, counters);
        }
        continue;
      }
      switch (job.shading) {
        case ShadingMode::flat: triangle<0>(job, tv, t, plane_of, phong, counters); break;
        case ShadingMode::gouraud: triangle<1>(job, tv, t, plane_of, phong, counters); break;
        default: triangle<2>(job, tv, t, plane_of, phong, counters); break;
      }
    }
    phong.flush();
  }

  // --- resolve -------------------------------------------------------------------------------

  static std::uint32_t unorm8(float v) {
    const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
    return static_cast<std::uint32_t>(c * 255.0f + 0.5f);  // as to_unorm8 (io/image_convert.hpp)
  }
  // A colour channel of 8-bit output: linear, or sRGB-encoded with the table's thresholds (the
  // search of io/srgb.hpp, written here again: no inline function is shared across ISA files).
  static std::uint32_t colour8(const TileView& tv, float v) {
    if (!tv.srgb) return unorm8(v);
    int k = 0;
    for (int step = 128; step >= 1; step >>= 1) {
      if (v >= tv.srgb[k + step]) k += step;
    }
    return static_cast<std::uint32_t>(k);
  }
  template <class A>
  static xsimd::batch<std::int32_t, A> unorm8(const xsimd::batch<float, A>& v) {
    using B = xsimd::batch<float, A>;
    const B c = xsimd::select(v > B(0.0f), xsimd::min(v, B(1.0f)), B(0.0f));
    return xsimd::batch_cast<std::int32_t>(c * B(255.0f) + B(0.5f));  // truncation, as the cast above
  }

  // The commonest resolve: 8-bit RGBA or BGRA, linear, no depth output, whole blocks across the
  // tile (fast_resolve). The same conversion as resolve() with nothing decided per pixel: one row
  // of the image at a time, a block's row of 8 pixels per step (avx512: two blocks' rows, 16
  // horizontally adjacent pixels, when both blocks were touched), the planes read at a fixed step.
  static bool fast_resolve(const TileView& tv, int x0, int x1, const ImageView& color, const DepthView* depth) {
    return !depth && !tv.srgb && color.format != PixelFormat::rgba32f && (x1 - x0) % kBlock == 0;
  }
  static std::uint32_t clear_word(const TileView& tv, int red_shift, int blue_shift) {
    return (colour8(tv, tv.clear[0]) << red_shift) | (colour8(tv, tv.clear[1]) << 8) |
           (colour8(tv, tv.clear[2]) << blue_shift) | (unorm8(tv.clear[3]) << 24);
  }
  static void resolve_unorm8(const TileView& tv, int x0, int y0, int x1, int y1, const ImageView& color) {
    static_assert(W == 4 || W == 8 || W == 16);
    const int red_shift = color.format == PixelFormat::bgra8 ? 16 : 0, blue_shift = 16 - red_shift;
    const int blocks_per_row = tv.size / kBlock, blocks = (x1 - x0) / kBlock;
    const std::uint32_t clear = clear_word(tv, red_shift, blue_shift);
    constexpr int kLane = W < kBlock ? W : kBlock;  // pixels per store in the one-block steps
    using Half = std::conditional_t<W == 16, xsimd::batch<std::int32_t, xsimd::fma3<xsimd::avx2>>, I>;
    using HalfF = std::conditional_t<W == 16, xsimd::batch<float, xsimd::fma3<xsimd::avx2>>, F>;
    static_assert(Half::size == kLane);
    const auto word = [&](const auto& r, const auto& g, const auto& b, const auto& a) {
      return (unorm8(r) << red_shift) | (unorm8(g) << 8) | (unorm8(b) << blue_shift) | (unorm8(a) << 24);
    };
    for (int y = y0; y < y1; ++y) {
      const int ty = y - y0;
      const int image_row = color.y_up ? color.height - 1 - y : y;
      auto* dst = reinterpret_cast<std::int32_t*>(static_cast<std::uint8_t*>(color.data) +
                                                  static_cast<std::size_t>(image_row) * color.stride_bytes +
                                                  4 * static_cast<std::size_t>(x0));
      const std::uint8_t* touched = tv.touched + (ty / kBlock) * blocks_per_row;
      const std::size_t first = static_cast<std::size_t>((ty / kBlock) * blocks_per_row) * kBlockPixels +
                                static_cast<std::size_t>((ty % kBlock) * kBlock);
      const float *r = tv.plane[0] + first, *g = tv.plane[1] + first, *b = tv.plane[2] + first,
                  *a = tv.plane[3] + first;
      for (int bx = 0; bx < blocks;) {
        std::int32_t* out = dst + bx * kBlock;
        const std::size_t at = static_cast<std::size_t>(bx) * kBlockPixels;
        if constexpr (W == 16) {  // the rows of two touched blocks in one batch, the left block low
          if (bx + 1 < blocks && touched[bx] && touched[bx + 1]) {
            const auto pair = [&](const float* p) {
              p += at;
              return F(_mm512_insertf32x8(_mm512_castps256_ps512(_mm256_load_ps(p)), _mm256_load_ps(p + kBlockPixels), 1));
            };
            word(pair(r), pair(g), pair(b), pair(a)).store_unaligned(out);  // image rows need not be aligned
            bx += 2;
            continue;
          }
        }
        if (!touched[bx]) {
          for (int i = 0; i < kBlock; i += kLane) Half(static_cast<std::int32_t>(clear)).store_unaligned(out + i);
        } else {
          for (int i = 0; i < kBlock; i += kLane) {
            word(HalfF::load_aligned(r + at + i), HalfF::load_aligned(g + at + i), HalfF::load_aligned(b + at + i),
                 HalfF::load_aligned(a + at + i))
                .store_unaligned(out + i);
          }
        }
        ++bx;
      }
    }
  }

  // Resolve works on rows of 8 pixels: avx512 uses its avx2 half (see raster_simd_avx512.cpp).
  static void resolve(const TileView& tv, int x0, int y0, int x1, int y1, const ImageView& color,
                      const DepthView* depth) {
    const int blocks_per_row = tv.size / kBlock;
    const int width = x1 - x0;
    // RGBA8 and BGRA8 as little-endian words: channel c goes to byte shift[c] / 8.
    const int red_shift = color.format == PixelFormat::bgra8 ? 16 : 0, blue_shift = 16 - red_shift;
    const std::uint32_t clear_word = TileKernel::clear_word(tv, red_shift, blue_shift);
    const std::uint8_t clear_bytes[4] = {static_cast<std::uint8_t>(clear_word), static_cast<std::uint8_t>(clear_word >> 8),
                                         static_cast<std::uint8_t>(clear_word >> 16),
                                         static_cast<std::uint8_t>(clear_word >> 24)};
    if (fast_resolve(tv, x0, x1, color, depth)) {
      resolve_unorm8(tv, x0, y0, x1, y1, color);
      return;
    }
    for (int y = y0; y < y1; ++y) {
      const int ty = y - y0;
      const int image_row = color.y_up ? color.height - 1 - y : y;
      auto* row = static_cast<std::uint8_t*>(color.data) + static_cast<std::size_t>(image_row) * color.stride_bytes;
      // Depth and float colour buffers may have any alignment (image.hpp): bytes and memcpy only.
      std::uint8_t* depth_row = nullptr;
      if (depth) {
        const int depth_row_index = depth->y_up ? depth->height - 1 - y : y;
        depth_row = reinterpret_cast<std::uint8_t*>(depth->data) + static_cast<std::size_t>(depth_row_index) * depth->stride_bytes;
      }
      for (int bx = 0; bx * kBlock < width; ++bx) {
        const int block = (ty / kBlock) * blocks_per_row + bx;
        const std::size_t src =
            static_cast<std::size_t>(block) * kBlockPixels + static_cast<std::size_t>((ty % kBlock) * kBlock);
        const int x = x0 + bx * kBlock;
        const int n = imin(kBlock, width - bx * kBlock);
        if (!tv.touched[block]) {  // still the clear colour: converted once per tile, as below
          if (depth_row) {
            const float f = tv.depth_reversed ? 0.0f - tv.depth_far : tv.depth_far;  // the output's far value (0, not -0)
            const float far_depth[kBlock] = {f, f, f, f, f, f, f, f};
            std::memcpy(depth_row + 4 * static_cast<std::size_t>(x), far_depth, 4 * static_cast<std::size_t>(n));
          }
          if (color.format == PixelFormat::rgba32f) {
            for (int i = 0; i < n; ++i) std::memcpy(row + 16 * static_cast<std::size_t>(x + i), tv.clear, 16);
          } else {
            auto* dst = reinterpret_cast<std::int32_t*>(row + 4 * static_cast<std::size_t>(x));
            int i = 0;
            if constexpr (W <= kBlock) {
              for (; i + W <= n; i += W) I(static_cast<std::int32_t>(clear_word)).store_unaligned(dst + i);
            }
            for (; i < n; ++i) std::memcpy(dst + i, clear_bytes, 4);
          }
          continue;
        }
        const float* r = tv.plane[0] + src;
        const float* g = tv.plane[1] + src;
        const float* b = tv.plane[2] + src;
        const float* a = tv.plane[3] + src;
        if (depth_row) {
          if (tv.depth_reversed) {  // the output is near / w: the stored value negated
            float out[kBlock];
            for (int i = 0; i < n; ++i) out[i] = 0.0f - tv.plane[4][src + static_cast<std::size_t>(i)];
            std::memcpy(depth_row + 4 * static_cast<std::size_t>(x), out, 4 * static_cast<std::size_t>(n));
          } else {
            std::memcpy(depth_row + 4 * static_cast<std::size_t>(x), tv.plane[4] + src, 4 * static_cast<std::size_t>(n));
          }
        }
        if (color.format == PixelFormat::rgba32f) {
          float rgba[4 * kBlock];
          for (int i = 0; i < n; ++i) {
            rgba[4 * i + 0] = r[i], rgba[4 * i + 1] = g[i], rgba[4 * i + 2] = b[i], rgba[4 * i + 3] = a[i];
          }
          std::memcpy(row + 16 * static_cast<std::size_t>(x), rgba, 16 * static_cast<std::size_t>(n));
          continue;
        }
        auto* dst = reinterpret_cast<std::uint32_t*>(row + 4 * static_cast<std::size_t>(x));
        int i = 0;
        if constexpr (W <= kBlock) {
          if (n == kBlock && !tv.srgb) {
            for (; i < kBlock; i += W) {
              const I word = (unorm8(F::load_unaligned(r + i)) << red_shift) |
                             (unorm8(F::load_unaligned(g + i)) << 8) |
                             (unorm8(F::load_unaligned(b + i)) << blue_shift) | (unorm8(F::load_unaligned(a + i)) << 24);
              // Unaligned store: image rows need not be 4-byte aligned.
              word.store_unaligned(reinterpret_cast<std::int32_t*>(dst + i));
            }
          }
        }
        for (; i < n; ++i) {
          const std::uint32_t u = (colour8(tv, r[i]) << red_shift) | (colour8(tv, g[i]) << 8) | (colour8(tv, b[i]) << blue_shift) |
                                  (unorm8(a[i]) << 24);
          auto* d = reinterpret_cast<std::uint8_t*>(dst + i);
          d[0] = static_cast<std::uint8_t>(u), d[1] = static_cast<std::uint8_t>(u >> 8);
          d[2] = static_cast<std::uint8_t>(u >> 16), d[3] = static_cast<std::uint8_t>(u >> 24);
        }
      }
    }
  }
};

}  // namespace
}  // namespace facet::raster::simd
