// Internal: the SIMD tile rasterizer, a template on the xsimd architecture. It covers triangles
// and tests depth; each batch of pixels that passes goes, with the triangle's planes evaluated at
// its block's origin, to the draw's pixel program (pixel/programs_simd.hpp). Only the per-ISA
// files tile/kernels_{sse2,avx2,avx512}.cpp include this header; each instantiates it once with its
// own flags, always with -ffp-contract=off so that every ISA does the same IEEE operations in the
// same order: images are then byte-identical across sse2, avx2 and avx512
// (tests/raster_simd_test.cpp). Everything here is a template on Arch or sits in an unnamed
// namespace, so no inline function is shared with another ISA's object file (an inline function
// compiled into files with different ISA flags is merged by the linker, and the wider copy may run
// on a CPU without it).
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

#include "pixel/batch_simd.hpp"
#include "pixel/phong_simd.hpp"
#include "pixel/programs_simd.hpp"
#include "tile/kernels.hpp"

namespace facet::tile::simd {
namespace {

using namespace facet::raster;  // the set-up's records (ScreenTriangle, planes, samples) it covers

template <class Arch>
struct TileKernel {
  using T = pixel::simd::Types<Arch>;
  using F = typename T::F;
  using I = typename T::I;
  using BF = typename T::BF;
  using BI = typename T::BI;
  static constexpr int W = T::W;
  static constexpr int kBatches = T::kBatches;
  using PhongBatch = pixel::simd::PhongBatch<Arch>;

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

  // Marks every block of the tile untouched (the lazy clear; see TileView), or touched when the
  // planes were filled before (TileView::prefilled).
  static void clear(const TileJob& job, const TileView& tv) {
    const int nbx = (job.x1 - job.x0 + kBlock - 1) / kBlock, nby = (job.y1 - job.y0 + kBlock - 1) / kBlock;
    const int blocks_per_row = tv.size / kBlock;
    const std::uint8_t state = tv.prefilled ? 1 : 0;
    for (int by = 0; by < nby; ++by) {
      for (int bx = 0; bx < nbx; ++bx) tv.touched[by * blocks_per_row + bx] = state;
    }
  }

  // First triangle to reach a block: fill it (every sample of it) with the clear colour and far depth.
  static void touch(const TileView& tv, int block, std::size_t base) {
    if (tv.touched[block]) return;
    tv.touched[block] = 1;
    const F values[5] = {F(tv.clear[0]), F(tv.clear[1]), F(tv.clear[2]), F(tv.clear[3]), F(tv.depth_far)};
    for (int s = 0; s < tv.samples; ++s) {
      const std::size_t at = base + static_cast<std::size_t>(s) * tv.sample_stride;
      for (int c = 0; c < 5; ++c) {
        for (int b = 0; b < kBatches; ++b) values[c].store_unaligned(tv.plane[c] + at + b * W);
      }
    }
  }

  // One triangle, covered and depth-tested, its passing batches run by Program. Counters and plane
  // pointers are locals: xsimd registers are may_alias vector types, so accumulating into a
  // reference (or reading pointers through one) after every pixel store would force a
  // store-to-load round trip per batch. Blocks inside every edge and the tile run a separate
  // instantiation of the batch (kFull: no per-batch coverage work or branches).
  // Multisampled (kMulti): every batch tests coverage and depth at each of its pixels' samples and
  // the program runs once for the lanes where any sample passed (pixel::simd::SampleLanes), with
  // the attributes at the pixel centre, storing into each sample that passed: GL's per-pixel
  // shading, every sample a triangle covers gets the colour of the pixel's centre.
  template <class Program, bool kMulti = false>
  static void triangle(const TileJob& job, const TileView& tv, const ScreenTriangle& t, PhongBatch& phong,
                       TileCounters& counters) {
    I tested(0);                      // per lane, batches partly covered
    std::uint64_t whole_tested = 0;   // whole batches
    float* const planes[5] = {tv.plane[0], tv.plane[1], tv.plane[2], tv.plane[3], tv.plane[4]};
    const int x0 = imax(t.min_px, job.x0), x1 = imin(t.max_px, job.x1 - 1);
    const int y0 = imax(t.min_py, job.y0), y1 = imin(t.max_py, job.y1 - 1);
    if (x0 > x1 || y0 > y1) return;
    const int bx0 = (x0 - job.x0) / kBlock, bx1 = (x1 - job.x0) / kBlock;
    const int by0 = (y0 - job.y0) / kBlock, by1 = (y1 - job.y0) / kBlock;
    const int rect_w = job.x1 - job.x0, rect_h = job.y1 - job.y0;
    const int blocks_per_row = tv.size / kBlock;
    const Lanes& L = lanes();

    // Edges: 64-bit values at the first block's first pixel centre (biased by the top-left rule),
    // steps between blocks, and the corner offsets that bound a block's values.
    std::int64_t e_row[3], step_bx[3], step_by[3], lo[3], hi[3];
    std::int32_t a32[3], b32[3];
    I lane_ab[3];  // A i + B j for the lanes of batch 0
    {
      const std::int64_t px = std::int64_t(job.x0 + bx0 * kBlock) * kSubpixelOne + kPixelCentre;
      const std::int64_t py = std::int64_t(job.y0 + by0 * kBlock) * kSubpixelOne + kPixelCentre;
      for (int k = 0; k < 3; ++k) {
        const raster::Edge edge = raster::edge_at(t.x, t.y, t.bias, k, px, py);
        const std::int64_t A = edge.A, B = edge.B;
        e_row[k] = edge.at;
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

    // The planes the program asked for: depth here, 1/w and its attributes there.
    const Draw& d = job.draws[t.object];
    const pixel::simd::Context<Arch> context{job, tv, t, d, phong, planes};
    Program program(context);
    constexpr int kAttributes = Program::kAttributes;
    pixel::simd::PlaneEval<Arch> z_plane;
    pixel::simd::Interpolants<Arch, kAttributes> in;
    z_plane.set(t.plane[kPlaneZ]);
    if constexpr (Program::kClipW) {
      in.count = Program::attributes(d);
      in.w.set(t.plane[kPlaneInvW]);
      for (int a = 0; a < in.count; ++a) in.attr[a].set(t.plane[kPlaneAttr + Program::plane(d, a)]);
    }
    const double vx = double(t.x[0]) / kSubpixelOne, vy = double(t.y[0]) / kSubpixelOne;
    // kMulti: each sample's edge values less the pixel centre's (exact), their extremes (which
    // bound a block's samples), and its depth offset.
    const int samples = kMulti ? tv.samples : 1;
    std::int64_t delta[kMulti ? kMaxSamples : 1][3] = {}, dmin[3] = {}, dmax[3] = {};
    double zxs[kMulti ? kMaxSamples : 1] = {}, zys[kMulti ? kMaxSamples : 1] = {};
    float z_os[kMulti ? kMaxSamples : 1] = {};
    pixel::simd::SampleLanes<Arch> ms;
    if constexpr (kMulti) {
      ms.count = samples;
      ms.stride = tv.sample_stride;
      for (int s = 0; s < samples; ++s) {
        const std::int64_t ox = tv.sample_x[s] - kPixelCentre, oy = tv.sample_y[s] - kPixelCentre;
        zxs[s] = double(ox) / kSubpixelOne, zys[s] = double(oy) / kSubpixelOne;
        for (int k = 0; k < 3; ++k) {
          delta[s][k] = std::int64_t(a32[k]) * ox + std::int64_t(b32[k]) * oy;
          dmin[k] = s == 0 ? delta[s][k] : std::min(dmin[k], delta[s][k]);
          dmax[k] = s == 0 ? delta[s][k] : std::max(dmax[k], delta[s][k]);
        }
      }
    }

    for (int by = by0; by <= by1; ++by) {
      std::int64_t e[3] = {e_row[0], e_row[1], e_row[2]};
      for (int bx = bx0; bx <= bx1; ++bx, e[0] += step_bx[0], e[1] += step_bx[1], e[2] += step_bx[2]) {
        // Outside an edge (kMulti: at every sample).
        if (e[0] + hi[0] + dmax[0] < 0 || e[1] + hi[1] + dmax[1] < 0 || e[2] + hi[2] + dmax[2] < 0) continue;
        // Edges the block straddles, with their per-block lane values A i + B j + floor(E / 256)
        // (kMulti: per sample, in the batch).
        int partial = 0;
        I edge_base[3] = {I(0), I(0), I(0)};
        for (int k = 0; k < 3; ++k) {
          if (e[k] + lo[k] + dmin[k] >= 0) continue;  // the whole block is inside this edge
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
        if constexpr (kMulti) {
          for (int s = 0; s < samples; ++s) z_os[s] = z_plane.origin(cx + zxs[s], cy + zys[s]);
        }
        if constexpr (Program::kClipW) {
          in.w_o = in.w.origin(cx, cy);
          for (int a = 0; a < in.count; ++a) in.attr_o[a] = in.attr[a].origin(cx, cy);
        }

        // One batch of W pixels; Full: the block is inside every edge and the tile's rectangle, so
        // coverage is all lanes.
        auto shade_batch = [&](auto full_tag, int b) {
          constexpr bool kFull = decltype(full_tag)::value;
          if constexpr (kMulti) {
            const int i0 = (b * W) % kBlock, j0 = (b * W) / kBlock;
            const F fi = F::load_aligned(L.fi + b * W), fj = F::load_aligned(L.fj + b * W);
            BI inside_tile(true);
            if (clipped) {
              inside_tile = (I::load_aligned(L.ii + b * W) < I(rect_w - ox)) & (I::load_aligned(L.jj + b * W) < I(rect_h - oy));
            }
            BF any(false);
            for (int s = 0; s < samples; ++s) {
              BI cover_s = inside_tile;
              if (!kFull && partial) {
                I acc(0);
                for (int k = 0; k < 3; ++k) {
                  if (partial & (1 << k)) {
                    acc = acc | (lane_ab[k] + I(static_cast<std::int32_t>((e[k] + delta[s][k]) >> kSubpixelBits)) +
                                 I(a32[k] * i0 + b32[k] * j0));
                  }
                }
                cover_s = cover_s & (acc >= I(0));
              }
              F z = z_plane.at(z_os[s], fi, fj);
              z = xsimd::select(z > F(tv.depth_lo), xsimd::min(z, F(tv.depth_far)), F(tv.depth_lo));
              const std::size_t at = base + static_cast<std::size_t>(b * W) + static_cast<std::size_t>(s) * tv.sample_stride;
              ms.pass[s] = (z < F::load_unaligned(planes[4] + at)) & xsimd::bool_cast(cover_s);
              ms.z[s] = z;
              tested += xsimd::select(cover_s, I(1), I(0));
              any = any | ms.pass[s];
            }
            if (!xsimd::any(any)) return;
            program.template batch_samples<kFull>(in, fi, fj, ms, any, base + static_cast<std::size_t>(b * W));
            return;
          }
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
          program.template batch<kFull>(in, fi, fj, z, pass, base + static_cast<std::size_t>(b * W));
        };
        // Multisampled blocks take one instantiation of the batch (the samples' work dominates,
        // and a second one costs the kernels' compile time).
        bool whole = false;
        if constexpr (!kMulti) {
          if (!partial && !clipped) {
            for (int b = 0; b < kBatches; ++b) shade_batch(std::true_type{}, b);
            whole = true;
          }
        }
        if (!whole) {
          // Only the batches that meet the triangle's bounds: a small triangle touches a few rows
          // of a block, the other batches are not worked.
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
        program.end_block(in);
      }
      for (int k = 0; k < 3; ++k) e_row[k] += step_by[k];
    }
    // Lane counters cannot overflow within one triangle and tile (< 2^16 pixels).
    counters.tested += static_cast<std::uint32_t>(xsimd::hadd(tested)) + whole_tested;
    counters.filled += static_cast<std::uint32_t>(xsimd::hadd(program.filled.lanes)) + program.filled.whole;
  }

  static void raster(const TileJob& job, const TileView& tv, TileCounters& counters) {
    using namespace pixel::simd;
    clear(job, tv);
    PhongBatch phong{job.phong, &tv, &job};
    for (std::size_t n = 0; n < job.bin_size; ++n) {
      if (n + 6 < job.bin_size) {  // six triangles ahead: set-up wrote them long ago, so they are not in cache
        const std::uint32_t ahead = job.bin[n + 6];
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
      if (job.shading == ShadingMode::phong) {
        if (phong.count > 0 && (t.object != phong.object || t.alpha != phong.alpha)) phong.flush();
        phong.object = t.object;
        phong.alpha = t.alpha;
      }
      if (tv.samples > 1) {
        // Multisampled: the fused programs' draws run the general programs (in the float tier the
        // same bytes as its fused ones; a 16-bit tier draw keeps its fixed-point texels,
        // Draw::fixed_texels), so that only these five are compiled a second time, for samples.
        switch (job.draws[t.object].program) {
          case PixelProgram::flat: triangle<FlatProgram<Arch>, true>(job, tv, t, phong, counters); break;
          case PixelProgram::gouraud: triangle<GouraudProgram<Arch>, true>(job, tv, t, phong, counters); break;
          case PixelProgram::phong: triangle<PhongProgram<Arch>, true>(job, tv, t, phong, counters); break;
          case PixelProgram::surface:
          case PixelProgram::blend_alpha:
          case PixelProgram::blend_premultiplied:
          case PixelProgram::blend_add: triangle<SurfaceProgram<Arch, false>, true>(job, tv, t, phong, counters); break;
          default: triangle<SurfaceProgram<Arch, true>, true>(job, tv, t, phong, counters); break;
        }
        continue;
      }
      switch (job.draws[t.object].program) {
        case PixelProgram::flat: triangle<FlatProgram<Arch>>(job, tv, t, phong, counters); break;
        case PixelProgram::gouraud: triangle<GouraudProgram<Arch>>(job, tv, t, phong, counters); break;
        case PixelProgram::phong: triangle<PhongProgram<Arch>>(job, tv, t, phong, counters); break;
        case PixelProgram::surface: triangle<SurfaceProgram<Arch, false>>(job, tv, t, phong, counters); break;
        case PixelProgram::surface_textured: triangle<SurfaceProgram<Arch, true>>(job, tv, t, phong, counters); break;
        case PixelProgram::modulate: triangle<ModulateProgram<Arch, false>>(job, tv, t, phong, counters); break;
        case PixelProgram::modulate_fog: triangle<ModulateProgram<Arch, true>>(job, tv, t, phong, counters); break;
        case PixelProgram::modulate_fixed: triangle<ModulateProgram<Arch, false, true>>(job, tv, t, phong, counters); break;
        case PixelProgram::modulate_fog_fixed: triangle<ModulateProgram<Arch, true, true>>(job, tv, t, phong, counters); break;
        case PixelProgram::blend_alpha: triangle<BlendProgram<Arch, BlendMode::alpha>>(job, tv, t, phong, counters); break;
        case PixelProgram::blend_premultiplied:
          triangle<BlendProgram<Arch, BlendMode::premultiplied>>(job, tv, t, phong, counters);
          break;
        case PixelProgram::blend_add: triangle<BlendProgram<Arch, BlendMode::add>>(job, tv, t, phong, counters); break;
      }
    }
    phong.flush();
  }
};

}  // namespace
}  // namespace facet::tile::simd
