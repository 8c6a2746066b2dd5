// Internal: what the SIMD tile rasterizer hands a pixel program, as templates on the xsimd
// architecture: the batch types, the lanes of an 8x8 block, a triangle's planes evaluated at a
// block's origin (Interpolants), a batch of covered pixels that passed the depth test (Batch) and
// the program's fill counters. Included only by per-ISA files built with -ffp-contract=off;
// everything is a template or in an unnamed namespace (no inline function crosses ISA files).
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "pixel/program.hpp"
#include "raster/samples.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::pixel::simd {
namespace {

using pixel::kBlock;
using pixel::kBlockPixels;

template <class Arch>
struct Types {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using BF = xsimd::batch_bool<float, Arch>;
  using BI = xsimd::batch_bool<std::int32_t, Arch>;
  using U = xsimd::batch<std::uint32_t, Arch>;
  static constexpr int W = static_cast<int>(F::size);
  static constexpr int kBatches = kBlockPixels / W;
  static_assert(kBlockPixels % W == 0 && (W <= kBlock ? kBlock % W == 0 : W % kBlock == 0));
};

// Block-origin values and per-lane steps of one plane (raster::Plane).
template <class Arch>
struct PlaneEval {
  using F = typename Types<Arch>::F;
  double at_v0, dxd, dyd;
  F dx, dy;
  void set(const raster::Plane& p) {
    at_v0 = p.at_v0, dxd = p.dx, dyd = p.dy;
    dx = F(p.dx), dy = F(p.dy);
  }
  // Value at the block's first pixel centre, (cx, cy) relative to vertex 0: in double, rounded.
  float origin(double cx, double cy) const { return static_cast<float>(at_v0 + dxd * cx + dyd * cy); }
  // At lanes (fi, fj) of the block: the origin plus (i dx + j dy) in float.
  F at(float o, const F& fi, const F& fj) const { return F(o) + (fi * dx + fj * dy); }
};

// A triangle's 1/w plane and its first N attribute planes (over w) as a program asked for them
// (Program::plane), and their values at the running block's origin.
template <class Arch, int N>
struct Interpolants {
  using F = typename Types<Arch>::F;
  PlaneEval<Arch> w;
  PlaneEval<Arch> attr[N > 0 ? N : 1];
  float w_o = 0.0f;
  float attr_o[N > 0 ? N : 1] = {};
  int count = 0;  // attributes in use, <= N
  // Clip w at lanes (fi, fj): the eye-space depth, 1 / (1/w).
  F clip_w(const F& fi, const F& fj) const { return F(1.0f) / w.at(w_o, fi, fj); }
  // Attribute a over w at lanes (fi, fj); times clip_w, the perspective-correct attribute.
  F over_w(int a, const F& fi, const F& fj) const { return attr[a].at(attr_o[a], fi, fj); }
};

// Multisampling, shaded once per pixel (each program's batch_samples): per sample, the batch's lanes
// that its triangle covers and that pass its depth test, and its depth; sample s of the pixel at
// index p is at p + s * stride.
template <class Arch>
struct SampleLanes {
  int count = 0;
  std::size_t stride = 0;
  typename Types<Arch>::BF pass[raster::kMaxSamples];
  typename Types<Arch>::F z[raster::kMaxSamples];
};

// One batch of W pixels of a block: lane coordinates (i, j) in the block, the interpolated depth,
// the lanes covered and passing the depth test (multisampled: at any sample), the tile-buffer
// index of lane 0, and for a multisampled batch shaded once its samples (else null).
template <class Arch>
struct Batch {
  typename Types<Arch>::F fi, fj, z;
  typename Types<Arch>::BF pass;
  std::size_t at;
  const SampleLanes<Arch>* samples = nullptr;
};

// Pixels filled: per lane for partly passing batches, as a scalar for whole ones.
template <class Arch>
struct FillCounts {
  typename Types<Arch>::I lanes = typename Types<Arch>::I(0);
  std::uint64_t whole = 0;
  void add(const typename Types<Arch>::BF& pass) {
    using I = typename Types<Arch>::I;
    lanes += xsimd::select(xsimd::bool_cast(pass), I(1), I(0));
  }
  // Counts a batch that passed the depth test; true when every lane did.
  bool count(const typename Types<Arch>::BF& pass) {
    const bool all = xsimd::all(pass);
    if (all) {
      whole += Types<Arch>::W;
    } else {
      add(pass);
    }
    return all;
  }
};

// Stores v into plane c at the batch's pixels that pass (all: every lane passes); a multisampled
// batch into each sample that passes, depth (c = 4) as the sample's own.
template <class Arch>
inline void store(float* const (&planes)[5], int c, const Batch<Arch>& b, bool all,
                  const typename Types<Arch>::F& v) {
  using F = typename Types<Arch>::F;
  if (const SampleLanes<Arch>* ms = b.samples) {
    for (int s = 0; s < ms->count; ++s) {
      float* dst = planes[c] + b.at + static_cast<std::size_t>(s) * ms->stride;
      const F& value = c == 4 ? ms->z[s] : v;
      (xsimd::all(ms->pass[s]) ? value : xsimd::select(ms->pass[s], value, F::load_unaligned(dst))).store_unaligned(dst);
    }
    return;
  }
  float* dst = planes[c] + b.at;
  (all ? v : xsimd::select(b.pass, v, F::load_unaligned(dst))).store_unaligned(dst);
}

}  // namespace
}  // namespace facet::pixel::simd
