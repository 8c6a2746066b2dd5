// Internal: the light stage of per-pixel (Phong) programs on the SIMD path. Pixels that passed
// their tests are gathered with their interpolated eye-space position and normal (and, for a
// surface draw, the inputs of the program's tail that do not depend on lighting: albedo, texel,
// fog factor, emission) into the tile's PhongSink streams; at kPhongCapacity, or when the draw
// changes, the sink lights them in one structure-of-arrays call, then the program's tail (texture
// environment, emission, colour sum, fog, blend) runs on them and they are stored in entry order.
// Included only by per-ISA files built with -ffp-contract=off; templates only.
#pragma once

#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "pixel/batch_simd.hpp"
#include "pixel/stages.hpp"
#include "pixel/program.hpp"
#include "texture/sample_simd.hpp"

namespace facet::pixel::simd {
namespace {

using pixel::Draw;
using pixel::kPhongCapacity;
using pixel::PhongSink;
using pixel::TileJob;
using pixel::TileView;

// The compressing permutations of avx2: for each mask of 8 lanes, the set lanes in order, then zeros.
struct Compress8 {
  alignas(32) std::int32_t lanes[256][8];
};
constexpr Compress8 make_compress8() {
  Compress8 c{};
  for (int m = 0; m < 256; ++m) {
    int k = 0;
    for (int lane = 0; lane < 8; ++lane)
      if (m & (1 << lane)) c.lanes[m][k++] = lane;
  }
  return c;
}
inline constexpr Compress8 kCompress8 = make_compress8();

// Gathers Phong pixels and lights them with one object's shader; entries are scattered back in
// the order they were added, so when a pixel appears twice the later triangle wins (or, for a
// blended draw, blends over the earlier one).
template <class Arch>
struct PhongBatch {
  using F = typename Types<Arch>::F;
  using BF = typename Types<Arch>::BF;
  using U = typename Types<Arch>::U;
  static constexpr int W = Types<Arch>::W;
  alignas(64) static constexpr std::uint32_t kLaneIndex[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
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
  // (A compressing store straight to memory is microcoded on AMD Zen 4, and measured much slower.)
  template <int Q>
  bool append(float* const (&dst)[Q], const F (&v)[Q], int n, const BF& pass, std::size_t at, const U& samples) {
    if (count + W > kPhongCapacity) return false;
    const U pixel = U(static_cast<std::uint32_t>(at)) + U::load_aligned(kLaneIndex);
    int added = W;
    if (xsimd::all(pass)) {
      for (int q = 0; q < n; ++q) v[q].store_unaligned(dst[q] + count);
      pixel.store_unaligned(sink->pixel + count);
      if (sink->samples) samples.store_unaligned(sink->samples + count);
    } else if constexpr (W == 16) {
      const __mmask16 m = static_cast<typename BF::register_type>(pass);
      for (int q = 0; q < n; ++q) _mm512_storeu_ps(dst[q] + count, _mm512_maskz_compress_ps(m, v[q]));
      _mm512_storeu_si512(sink->pixel + count, _mm512_maskz_compress_epi32(m, pixel));
      if (sink->samples) _mm512_storeu_si512(sink->samples + count, _mm512_maskz_compress_epi32(m, samples));
      added = __builtin_popcount(m);
    } else if constexpr (W == 8) {
      const int m = _mm256_movemask_ps(pass);
      const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompress8.lanes[m]));
      for (int q = 0; q < n; ++q) _mm256_storeu_ps(dst[q] + count, _mm256_permutevar8x32_ps(v[q], order));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(sink->pixel + count), _mm256_permutevar8x32_epi32(pixel, order));
      if (sink->samples) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sink->samples + count), _mm256_permutevar8x32_epi32(samples, order));
      }
      added = __builtin_popcount(static_cast<unsigned>(m));
    } else {
      return false;
    }
    count += added;
    if (count == kPhongCapacity) flush();
    return true;
  }

  // Appends the passing lanes of v's first n streams (into dst) for the pixels at tile-buffer
  // index `at` onwards: as vectors (append) or lane by lane. Multisampled and shaded once (ms):
  // each entry with the samples it is stored to.
  template <int Q>
  void gather(float* const (&dst)[Q], const F (&v)[Q], int n, const BF& pass, std::size_t at,
              const SampleLanes<Arch>* ms = nullptr) {
    U samples(1u);
    if (ms) {
      samples = U(0u);
      for (int s = 0; s < ms->count; ++s) {
        // 1.0f where the sample passed (0x3f800000: bit 23 set), 0 elsewhere, to bit s.
        const U on = xsimd::bitwise_cast<U>(xsimd::select(ms->pass[s], F(1.0f), F(0.0f)));
        samples = samples | (((on >> 23) & U(1u)) << s);
      }
    }
    if (append(dst, v, n, pass, at, samples)) return;
    alignas(64) float values[Q][W];
    alignas(64) float mask[W];
    alignas(64) std::uint32_t lane_samples[W];
    for (int q = 0; q < n; ++q) v[q].store_aligned(values[q]);
    xsimd::select(pass, F(1.0f), F(0.0f)).store_aligned(mask);
    samples.store_aligned(lane_samples);
    for (int lane = 0; lane < W; ++lane) {
      if (mask[lane] == 0.0f) continue;
      const int k = count++;
      for (int q = 0; q < n; ++q) dst[q][k] = values[q][lane];
      sink->pixel[k] = static_cast<std::uint32_t>(at + static_cast<std::size_t>(lane));
      if (sink->samples) sink->samples[k] = lane_samples[lane];
      if (count == kPhongCapacity) flush();
    }
  }

  void flush() {
    if (count == 0) return;
    int padded = (count + 15) / 16 * 16;
    PhongSink& s = *sink;
    float* const streams[] = {s.px,       s.py,       s.pz,       s.nx,       s.ny,       s.nz,       s.ao,
                              s.ar,       s.ag,       s.ab,       s.carry[0], s.carry[1], s.carry[2],
                              s.carry[3], s.carry[4], s.carry[5], s.carry[6], s.carry[7]};
    static_assert(pixel::kMaxCarried == 8);
    for (float* f : streams) {
      for (int k = count; k < padded; ++k) f[k] = 0.0f;
    }
    s.shade(s.context, object, static_cast<std::size_t>(count), static_cast<std::size_t>(padded));
    const Draw& d = job->draws[object];
    if (!pixel::runs_surface_stages(d.program)) {
      for (int k = 0; k < count;) {
        if (const std::uint32_t m = run_at(k)) {  // W consecutive pixels with the same samples: stored as vectors
          for (std::uint32_t left = m; left; left &= left - 1) {
            const std::size_t p = s.pixel[k] + sample_offset(left);
            F::load_unaligned(s.r + k).store_unaligned(tile->plane[0] + p);
            F::load_unaligned(s.g + k).store_unaligned(tile->plane[1] + p);
            F::load_unaligned(s.b + k).store_unaligned(tile->plane[2] + p);
            F(alpha).store_unaligned(tile->plane[3] + p);
          }
          k += W;
          continue;
        }
        for (std::uint32_t left = entry_samples(k); left; left &= left - 1) {
          const std::size_t p = s.pixel[k] + sample_offset(left);
          tile->plane[0][p] = s.r[k];
          tile->plane[1][p] = s.g[k];
          tile->plane[2][p] = s.b[k];
          tile->plane[3][p] = alpha;
        }
        ++k;
      }
      count = 0;
      return;
    }
    // The surface program's tail on the lit pixels, W at a time; the colour and alpha replace
    // r, g, b and carry[0]. Then blend and store in entry order.
    const Fog& fog = *job->fog;
    auto level0 = [](const texture::Sampler& m, const F& u, const F& v, F(&rgba)[4]) {
      texture::simd::SampleSimd<Arch>::sample(m, u, v, F(0.0f), rgba);
    };
    for (int k = 0; k < padded; k += W) {
      const F p[3] = {F::load_unaligned(s.r + k), F::load_unaligned(s.g + k), F::load_unaligned(s.b + k)};
      const F sec[3] = {F::load_unaligned(s.sr + k), F::load_unaligned(s.sg + k), F::load_unaligned(s.sb + k)};
      const F position[3] = {F::load_unaligned(s.px + k), F::load_unaligned(s.py + k), F::load_unaligned(s.pz + k)};
      const F normal[3] = {F::load_unaligned(s.nx + k), F::load_unaligned(s.ny + k), F::load_unaligned(s.nz + k)};
      F c[4];
      pixel::lit_surface_colour(d, fog, p, sec, position, normal, [&](int q) { return F::load_unaligned(s.carry[q] + k); },
                                F(alpha), level0, c);
      c[0].store_unaligned(s.r + k);
      c[1].store_unaligned(s.g + k);
      c[2].store_unaligned(s.b + k);
      c[3].store_unaligned(s.carry[0] + k);
    }
    for (int k = 0; k < count;) {
      if (const std::uint32_t m = run_at(k)) {  // W consecutive pixels: blended as vectors (the same operations per pixel)
        const F c[4] = {F::load_unaligned(s.r + k), F::load_unaligned(s.g + k), F::load_unaligned(s.b + k),
                        F::load_unaligned(s.carry[0] + k)};
        for (std::uint32_t left = m; left; left &= left - 1) {  // each sample over its own destination
          const std::size_t p = s.pixel[k] + sample_offset(left);
          F dst[4];
          for (int ch = 0; ch < 4; ++ch) dst[ch] = F::load_unaligned(tile->plane[ch] + p);
          pixel::blend(d, c, dst);
          for (int ch = 0; ch < 4; ++ch) dst[ch].store_unaligned(tile->plane[ch] + p);
        }
        k += W;
        continue;
      }
      const float c[4] = {s.r[k], s.g[k], s.b[k], s.carry[0][k]};
      for (std::uint32_t left = entry_samples(k); left; left &= left - 1) {
        const std::size_t p = s.pixel[k] + sample_offset(left);
        float dst[4] = {tile->plane[0][p], tile->plane[1][p], tile->plane[2][p], tile->plane[3][p]};
        pixel::blend(d, c, dst);
        for (int ch = 0; ch < 4; ++ch) tile->plane[ch][p] = dst[ch];
      }
      ++k;
    }
    count = 0;
  }
  // Entry k's samples (bit 0 alone for one sample), and the index offset of the lowest sample
  // left in a mask.
  std::uint32_t entry_samples(int k) const { return sink->samples ? sink->samples[k] : 1u; }
  std::size_t sample_offset(std::uint32_t left) const {
    return static_cast<std::size_t>(__builtin_ctz(left)) * tile->sample_stride;
  }
  // If entries k .. k + W - 1 exist, are the pixels pixel[k] .. pixel[k] + W - 1 (a whole batch,
  // append) and go to the same samples, those samples' mask (else 0): distinct pixels, so storing
  // them at once keeps the entry order's result.
  std::uint32_t run_at(int k) const {
    if (k + W > count) return 0;
    const U first(sink->pixel[k]);
    if (!xsimd::all(U::load_unaligned(sink->pixel + k) == first + U::load_aligned(kLaneIndex))) return 0;
    if (!sink->samples) return 1;
    const std::uint32_t m = sink->samples[k];
    return xsimd::all(U::load_unaligned(sink->samples + k) == U(m)) ? m : 0;
  }
};

}  // namespace
}  // namespace facet::pixel::simd
