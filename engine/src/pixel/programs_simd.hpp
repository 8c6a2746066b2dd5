// Internal: the pixel programs of the SIMD path, templates on the xsimd architecture, each built
// from the stages of stages.hpp. The tile rasterizer (tile/raster_simd.hpp) covers a triangle's
// blocks and tests depth; it hands each batch of passing pixels, with the planes the program asked
// for evaluated at the block's origin, to the draw's program (Draw::program, chosen by the frame
// plan):
//   FlatProgram      store depth, the triangle's colour
//   GouraudProgram   store depth, interpolate the colour, store
//   PhongProgram     store depth, interpolate position and normal, light (phong_simd.hpp), store
//   SurfaceProgram   the general program, every stage as the draw's settings say (stages.hpp's
//                    order); with a texture, batches are held and sampled kHold at a time
//   BlendProgram     Gouraud, untextured, blended: the blend mode fixed at compile time
//   ModulateProgram  the commonest textured case with its settings fixed at compile time
//                    (Gouraud, GL_MODULATE, separate specular, opaque, no alpha test, no emission
//                    after the texture; fog or none): the same stage functions in the same order
//                    as SurfaceProgram runs them for those settings, so the same bits, without the
//                    branches.
// Multisampled tiles call batch_samples instead of batch (flat, Gouraud, Phong and the general
// programs; the fused ones' draws run the general programs then): the lanes where any sample
// passed, with each sample's lanes and depth (SampleLanes); the program shades them once and its
// stores go to each sample that passed (store(), or its own per-sample depth and blend loops).
// Included only by per-ISA files built with -ffp-contract=off; templates only.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "pixel/batch_simd.hpp"
#include "pixel/phong_simd.hpp"
#include "pixel/stages.hpp"
#include "pixel/program.hpp"
#include "texture/sample_fixed_simd.hpp"
#include "texture/sample_simd.hpp"

namespace facet::pixel::simd {
namespace {

using raster::ScreenTriangle;
using raster::Varying;

// What every program of a triangle sees: the job, the tile's planes, the triangle and its draw,
// and the Phong gather.
template <class Arch>
struct Context {
  const TileJob& job;
  const TileView& tv;
  const ScreenTriangle& t;
  const Draw& d;
  PhongBatch<Arch>& phong;
  float* const (&planes)[5];
};

// The tile's and so the programs' batch count of held textured batches: 2 x 16 lanes, 4 x 8 or
// 4 x 4, which measured best for the float sampler; the 16-bit tier's fused programs hold 4 on
// every ISA (its texels take fewer registers; 4 x 16 measured faster than 2 x 16 on avx512).
template <class Arch>
inline constexpr int kHold = Types<Arch>::W >= 16 ? 2 : 4;
inline constexpr int kHoldFixed = 4;

template <class Arch>
struct FlatProgram {
  using F = typename Types<Arch>::F;
  using BF = typename Types<Arch>::BF;
  static constexpr int kAttributes = 0;
  static constexpr bool kClipW = false;
  static int plane(const Draw&, int) { return 0; }
  static int attributes(const Draw&) { return 0; }
  const Context<Arch>& cx;
  F flat[4];
  FillCounts<Arch> filled;
  explicit FlatProgram(const Context<Arch>& c)
      : cx(c), flat{F(c.t.flat_rgb[0]), F(c.t.flat_rgb[1]), F(c.t.flat_rgb[2]), F(c.t.alpha)} {}
  template <bool kFull>
  void batch(const Interpolants<Arch, 0>&, const F& fi, const F& fj, const F& z, const BF& pass, std::size_t at) {
    body({fi, fj, z, pass, at});
  }
  template <bool kFull>
  void batch_samples(const Interpolants<Arch, 0>&, const F& fi, const F& fj, const SampleLanes<Arch>& ms, const BF& any,
                     std::size_t at) {
    body({fi, fj, F(0.0f), any, at, &ms});
  }
  void body(const Batch<Arch>& b) {
    const bool all = filled.count(b.pass);
    store(cx.planes, 4, b, all, b.z);
    for (int c = 0; c < 4; ++c) store(cx.planes, c, b, all, flat[c]);
  }
  void end_block(const Interpolants<Arch, 0>&) {}
};

template <class Arch>
struct GouraudProgram {
  using F = typename Types<Arch>::F;
  using BF = typename Types<Arch>::BF;
  static constexpr int kAttributes = 3;
  static constexpr bool kClipW = true;
  static int plane(const Draw& d, int a) { return d.layout.at(Varying::front_color) + a; }
  static int attributes(const Draw&) { return 3; }
  const Context<Arch>& cx;
  F alpha;
  FillCounts<Arch> filled;
  explicit GouraudProgram(const Context<Arch>& c) : cx(c), alpha(c.t.alpha) {}
  template <bool kFull>
  void batch(const Interpolants<Arch, 3>& in, const F& fi, const F& fj, const F& z, const BF& pass, std::size_t at) {
    body(in, {fi, fj, z, pass, at});
  }
  template <bool kFull>
  void batch_samples(const Interpolants<Arch, 3>& in, const F& fi, const F& fj, const SampleLanes<Arch>& ms, const BF& any,
                     std::size_t at) {
    body(in, {fi, fj, F(0.0f), any, at, &ms});
  }
  void body(const Interpolants<Arch, 3>& in, const Batch<Arch>& b) {
    const bool all = filled.count(b.pass);
    store(cx.planes, 4, b, all, b.z);
    const F inv_w = in.clip_w(b.fi, b.fj);
    for (int c = 0; c < 3; ++c) store(cx.planes, c, b, all, in.over_w(c, b.fi, b.fj) * inv_w);
    store(cx.planes, 3, b, all, alpha);
  }
  void end_block(const Interpolants<Arch, 3>&) {}
};

template <class Arch>
struct PhongProgram {
  using F = typename Types<Arch>::F;
  using BF = typename Types<Arch>::BF;
  static constexpr int kAttributes = 6;
  static constexpr bool kClipW = true;
  static int plane(const Draw& d, int a) {
    return a < 3 ? d.layout.at(Varying::eye_position) + a : d.layout.at(Varying::normal) + a - 3;
  }
  static int attributes(const Draw&) { return 6; }
  const Context<Arch>& cx;
  FillCounts<Arch> filled;
  explicit PhongProgram(const Context<Arch>& c) : cx(c) {}
  template <bool kFull>
  void batch(const Interpolants<Arch, 6>& in, const F& fi, const F& fj, const F& z, const BF& pass, std::size_t at) {
    body(in, {fi, fj, z, pass, at});
  }
  template <bool kFull>
  void batch_samples(const Interpolants<Arch, 6>& in, const F& fi, const F& fj, const SampleLanes<Arch>& ms, const BF& any,
                     std::size_t at) {
    body(in, {fi, fj, F(0.0f), any, at, &ms});
  }
  void body(const Interpolants<Arch, 6>& in, const Batch<Arch>& b) {
    const bool all = filled.count(b.pass);
    store(cx.planes, 4, b, all, b.z);
    const F inv_w = in.clip_w(b.fi, b.fj);
    F v[6];
    for (int a = 0; a < 6; ++a) v[a] = in.over_w(a, b.fi, b.fj) * inv_w;
    PhongSink& s = *cx.phong.sink;
    float* const dst[6] = {s.px, s.py, s.pz, s.nx, s.ny, s.nz};
    cx.phong.gather(dst, v, 6, b.pass, b.at, b.samples);
  }
  void end_block(const Interpolants<Arch, 6>&) {}
};

// The texture-coordinate and sampling stages of the SIMD programs.
template <class Arch>
struct Texturing {
  using F = typename Types<Arch>::F;
  using Sampler = texture::simd::SampleSimd<Arch>;
  template <int N>
  static Uv<F> uv(const Draw& d, const Interpolants<Arch, N>& in, const F& cw, const F& fi, const F& fj) {
    const int a = d.layout.at(Varying::uv);
    return uv_from_planes(d, in.over_w(a, fi, fj), in.over_w(a + 1, fi, fj), cw, in.attr[a].dx, in.attr[a].dy,
                          in.attr[a + 1].dx, in.attr[a + 1].dy, in.w.dx, in.w.dy);
  }
  // A map at (u, v) on its level 0 (environment maps: texgen coordinates have no derivatives).
  static void level0(const texture::Sampler& sampler, const F& u, const F& v, F (&rgba)[4]) {
    Sampler::sample(sampler, u, v, F(0.0f), rgba);
  }
  // One texture at those coordinates (RGBA in tex): the LOD, the sample.
  static void sample(const texture::Sampler& sampler, const Uv<F>& c, F (&tex)[4]) {
    const F lambda = Sampler::lod(sampler, c.dudx, c.dvdx, c.dudy, c.dvdy);
    Sampler::sample(sampler, c.u, c.v, lambda, tex);
  }
  // P batches' textures sampled at once (the sampler interleaves them, sample_simd.hpp), with the
  // triangle's level guess; Inline: always inlined.
  template <int P, bool Inline = false>
  [[gnu::always_inline]] inline static void sample(const texture::Sampler& sampler, const Uv<F> (&c)[P], F (&tex)[P][4], int& level_guess) {
    F u[P], v[P], lambda[P];
    for (int p = 0; p < P; ++p) {
      u[p] = c[p].u, v[p] = c[p].v;
      lambda[p] = Sampler::lod(sampler, c[p].dudx, c[p].dvdx, c[p].dudy, c[p].dvdy);
    }
    if constexpr (Inline) {
      Sampler::template sample_inline<P>(sampler, u, v, lambda, tex, &level_guess);
    } else {
      Sampler::template sample<P>(sampler, u, v, lambda, tex, &level_guess);
    }
  }
  // The same for the 16-bit tier (Draw::fixed_texels): the texels filtered in fixed point
  // (sample_fixed_simd.hpp), each byte then byte / 255 for the stages that follow (the scalar
  // path's twin: tile_raster.cpp).
  template <int P>
  [[gnu::always_inline]] inline static void sample_fixed(const texture::Sampler& sampler, const Uv<F> (&c)[P], F (&tex)[P][4],
                                                         int& level_guess) {
    using Fixed = texture::simd::SampleFixed<Arch>;
    using I = typename Types<Arch>::I;
    using U = typename Fixed::U;
    F u[P], v[P], lambda[P];
    for (int p = 0; p < P; ++p) {
      u[p] = c[p].u, v[p] = c[p].v;
      lambda[p] = Sampler::lod(sampler, c[p].dudx, c[p].dvdx, c[p].dudy, c[p].dvdy);
    }
    I texels[P];
    Fixed::template sample<P>(sampler, u, v, lambda, texels, &level_guess);
    for (int p = 0; p < P; ++p) {
      const U bits = xsimd::bitwise_cast<U>(texels[p]);
      for (int ch = 0; ch < 4; ++ch)
        tex[p][ch] = xsimd::batch_cast<float>(xsimd::bitwise_cast<I>((bits >> (8 * ch)) & U(0xffu))) * F(1.0f / 255.0f);
    }
  }
};

// Batches held until kHold of a block have passed, then run together (Body::run<P>), the rest at
// the block's end. Kept as arrays of each field: copying whole Batch records spilled them.
template <class Arch, int N, class Body, int Hold = kHold<Arch>>
struct Held {
  using F = typename Types<Arch>::F;
  using BF = typename Types<Arch>::BF;
  static constexpr int H = Hold;
  int held = 0;
  F fi[H], fj[H], z[H];
  BF pass[H];
  std::size_t at[H];
  void add(Body& body, const Interpolants<Arch, N>& in, const F& bfi, const F& bfj, const F& bz, const BF& bpass,
           std::size_t bat) {
    fi[held] = bfi, fj[held] = bfj, z[held] = bz, pass[held] = bpass, at[held] = bat;
    if (++held == H) {
      body.template run<H>(in, fi, fj, z, pass, at);
      held = 0;
    }
  }
  void finish(Body& body, const Interpolants<Arch, N>& in) {
    if (held == 1) body.template run<1>(in, fi, fj, z, pass, at);
    if constexpr (H > 2) {
      if (held == 2) body.template run<2>(in, fi, fj, z, pass, at);
    }
    if constexpr (H > 3) {
      if (held == 3) body.template run<3>(in, fi, fj, z, pass, at);
    }
    held = 0;
  }
};

template <class Arch, bool Textured>
struct SurfaceProgram {
  using F = typename Types<Arch>::F;
  using I = typename Types<Arch>::I;
  using BF = typename Types<Arch>::BF;
  static constexpr int kAttributes = raster::kMaxRasterAttributes;
  static constexpr bool kClipW = true;
  using In = Interpolants<Arch, kAttributes>;
  static int plane(const Draw&, int a) { return a; }
  static int attributes(const Draw& d) { return d.layout.raster; }
  const Context<Arch>& cx;
  FillCounts<Arch> filled;
  int level_guess = -1;  // the trilinear level the last batches read (SampleSimd::sample)
  Held<Arch, kAttributes, SurfaceProgram> held;
  explicit SurfaceProgram(const Context<Arch>& c) : cx(c) {}

  template <bool kFull>
  [[gnu::always_inline]] inline void batch(const In& in, const F& fi, const F& fj, const F& z, const BF& pass,
                                           std::size_t at) {
    if constexpr (Textured) {
      held.add(*this, in, fi, fj, z, pass, at);
    } else {
      untextured(in, {fi, fj, z, pass, at});
    }
  }
  template <bool kFull>
  void batch_samples(const In& in, const F& fi, const F& fj, const SampleLanes<Arch>& ms, const BF& any, std::size_t at) {
    const F z(0.0f);
    if constexpr (Textured) {
      run<1>(in, &fi, &fj, &z, &any, &at, &ms);
    } else {
      untextured(in, {fi, fj, z, any, at, &ms});
    }
  }
  [[gnu::always_inline]] inline void untextured(const In& in, const Batch<Arch>& b) {
    const F cw = in.clip_w(b.fi, b.fj);
    Uv<F> uv;  // not zeroed (measured: zeroing it per batch slowed the blended fill); read only with a uv varying
    if (cx.d.layout.has(Varying::uv)) uv = Texturing<Arch>::uv(cx.d, in, cw, b.fi, b.fj);
    tail(in, b, cw, nullptr, uv);
  }
  void end_block(const In& in) {
    if constexpr (Textured) held.finish(*this, in);
  }
  // P held batches: the texture sampled for all of them at once, then each batch's tail in order.
  template <int P>
  [[gnu::noinline]] void run(const In& in, const F* fi, const F* fj, const F* z, const BF* pass, const std::size_t* at,
                             const SampleLanes<Arch>* ms = nullptr) {
    F cw[P], tex[P][4];
    Uv<F> uv[P]{};
    for (int p = 0; p < P; ++p) {
      cw[p] = in.clip_w(fi[p], fj[p]);
      if (cx.d.layout.has(Varying::uv)) uv[p] = Texturing<Arch>::uv(cx.d, in, cw[p], fi[p], fj[p]);
    }
    if (cx.d.fixed_texels) {
      Texturing<Arch>::template sample_fixed<P>(*cx.d.texture, uv, tex, level_guess);
    } else {
      Texturing<Arch>::template sample<P>(*cx.d.texture, uv, tex, level_guess);
    }
    for (int p = 0; p < P; ++p) tail(in, {fi[p], fj[p], z[p], pass[p], at[p], ms}, cw[p], tex[p], uv[p]);
  }
  // One batch's program after its texture sample (texel: null when the draw has no texture).
  [[gnu::always_inline]] inline void tail(const In& in, const Batch<Arch>& b, const F& cw, const F* texel,
                                          const Uv<F>& uv) {
    const Draw& d = cx.d;
    const TileJob& job = cx.job;
    auto value = [&](int a) { return in.over_w(a, b.fi, b.fj) * cw; };
    const F alpha(cx.t.alpha);
    const F a = fragment_alpha(d, alpha, texel);
    const BF alpha_passes = a >= F(d.alpha_cutoff);  // the alpha test (per pixel)
    BF pass = b.pass & alpha_passes;
    // Multisampled (b.samples): each sample that passed coverage, depth, alpha to coverage and the
    // alpha test.
    SampleLanes<Arch> ms;
    if (b.samples) {
      ms = *b.samples;
      BF covered(false);
      for (int s = 0; s < ms.count; ++s) {
        ms.pass[s] = ms.pass[s] & alpha_passes;
        if (d.alpha_to_coverage) ms.pass[s] = ms.pass[s] & alpha_covers(a, s, ms.count);
        covered = covered | ms.pass[s];
      }
      pass = pass & covered;
    }
    if (!xsimd::any(pass)) return;
    filled.add(pass);
    const int samples = b.samples ? std::min(ms.count, raster::kMaxSamples) : 1;
    auto sample_at = [&](int s) { return b.at + (b.samples ? static_cast<std::size_t>(s) * ms.stride : 0); };
    if (d.depth_write) {
      for (int s = 0; s < samples; ++s) {
        float* depth = cx.planes[4] + sample_at(s);
        xsimd::select(b.samples ? ms.pass[s] : pass, b.samples ? ms.z[s] : b.z, F::load_unaligned(depth)).store_unaligned(depth);
      }
    }
    // A map at the pixel's coordinates moved by (du, dv), with its LOD (normal, bump, occlusion maps).
    auto sample_moved = [&](const texture::Sampler& s, float du, float dv, F(&t)[4]) {
      Uv<F> moved = uv;
      moved.u = moved.u + F(du), moved.v = moved.v + F(dv);
      Texturing<Arch>::sample(s, moved, t);
    };
    auto sample_uv = [&](const texture::Sampler& s, F(&t)[4]) { Texturing<Arch>::sample(s, uv, t); };
    auto to_phong = [&](const TailInputs<F>& tin) __attribute__((always_inline)) {  // light at the gather's flush
      F v[12 + pixel::kMaxCarried];
      const int position = d.layout.at(Varying::eye_position), albedo = d.layout.at(Varying::albedo);
      F normal[3];
      pixel_normal(d, value, cx.t.bitangent_negative(), sample_moved, normal);
      for (int c = 0; c < 3; ++c) {
        v[c] = value(position + c);
        v[3 + c] = normal[c];
        v[6 + c] = albedo >= 0 ? value(albedo + c) : F(1.0f);
      }
      int n = 9 + carry(d, *job.fog, tin, v + 9);
      PhongSink& s = *cx.phong.sink;
      float* dst[12 + pixel::kMaxCarried] = {s.px, s.py, s.pz, s.nx, s.ny, s.nz, s.ar, s.ag, s.ab};
      for (int k = 0; k < pixel::kMaxCarried; ++k) dst[9 + k] = s.carry[k];
      if (d.occlusion_map) {  // after the carried values: the lighting reads it from s.ao
        dst[n] = s.ao;
        v[n++] = occlusion<F>(d, [&](const texture::Sampler& sm, F(&t)[4]) { sample_moved(sm, 0.0f, 0.0f, t); });
      }
      if (d.metal_rough_map) {  // likewise: the lighting reads them from s.pm and s.pr
        F metal, rough;
        metal_rough<F>(d, [&](const texture::Sampler& sm, F(&t)[4]) { sample_moved(sm, 0.0f, 0.0f, t); }, metal, rough);
        dst[n] = s.pm, v[n++] = metal;
        dst[n] = s.pr, v[n++] = rough;
      }
      cx.phong.gather(dst, v, n, pass, b.at, b.samples ? &ms : nullptr);
    };
    F c[4];
    if (!surface_tail(d, *job.fog, job.shading, cx.t, value, cw, texel, alpha, sample_uv, sample_moved, Texturing<Arch>::level0,
                      to_phong, c)) {
      return;
    }
    for (int s = 0; s < samples; ++s) {  // each sample over its own destination
      const std::size_t at = sample_at(s);
      const BF passed = b.samples ? ms.pass[s] : pass;
      F old[4], out[4];
      for (int ch = 0; ch < 4; ++ch) out[ch] = old[ch] = F::load_unaligned(cx.planes[ch] + at);
      blend(d, c, out);
      for (int ch = 0; ch < 4; ++ch) xsimd::select(passed, out[ch], old[ch]).store_unaligned(cx.planes[ch] + at);
    }
  }
};

template <class Arch, bool Fogged, bool Fixed = false>
struct ModulateProgram {
  using F = typename Types<Arch>::F;
  static constexpr int kAttributes = raster::kMaxRasterAttributes;
  static constexpr bool kClipW = true;
  using BF = typename Types<Arch>::BF;
  using In = Interpolants<Arch, kAttributes>;
  static int plane(const Draw&, int a) { return a; }
  static int attributes(const Draw& d) { return d.layout.raster; }
  const Context<Arch>& cx;
  FillCounts<Arch> filled;
  int level_guess = -1;
  Held<Arch, kAttributes, ModulateProgram, Fixed ? kHoldFixed : kHold<Arch>> held;
  explicit ModulateProgram(const Context<Arch>& c) : cx(c) {}
  template <bool kFull>
  [[gnu::always_inline]] inline void batch(const In& in, const F& fi, const F& fj, const F& z, const BF& pass,
                                           std::size_t at) {
    held.add(*this, in, fi, fj, z, pass, at);
  }

  void end_block(const In& in) { held.finish(*this, in); }
  // On the narrower ISAs out of line, one function with its inlined sample; on avx512 inlined into
  // the rasterizer's loop (each measured faster than the other way).
  template <int P>
  [[gnu::always_inline]] inline void run(const In& in, const F* fi, const F* fj, const F* z, const BF* pass,
                                         const std::size_t* at) {
    if constexpr (Types<Arch>::W < 16) {
      run_out_of_line<P>(in, fi, fj, z, pass, at);
    } else {
      body<P>(in, fi, fj, z, pass, at);
    }
  }
  template <int P>
  [[gnu::noinline]] void run_out_of_line(const In& in, const F* fi, const F* fj, const F* z, const BF* pass,
                                         const std::size_t* at) {
    body<P>(in, fi, fj, z, pass, at);
  }
  template <int P>
  [[gnu::always_inline]] inline void body(const In& in, const F* fi, const F* fj, const F* z, const BF* pass,
                                          const std::size_t* at) {
    const Draw& d = cx.d;
    F cw[P], tex[P][4];
    Uv<F> uv[P];
    for (int p = 0; p < P; ++p) {
      cw[p] = in.clip_w(fi[p], fj[p]);
      uv[p] = Texturing<Arch>::uv(d, in, cw[p], fi[p], fj[p]);
    }
    if constexpr (Fixed) {
      Texturing<Arch>::template sample_fixed<P>(*d.texture, uv, tex, level_guess);
    } else {
      // Inlined on the narrower ISAs without fog, where out of line it measured slower.
      Texturing<Arch>::template sample<P, (Types<Arch>::W < 16 && !Fogged)>(*d.texture, uv, tex, level_guess);
    }
    // Locals, not members: stores through may_alias vector types would otherwise reload them.
    float* const planes[5] = {cx.planes[0], cx.planes[1], cx.planes[2], cx.planes[3], cx.planes[4]};
    const F alpha(cx.t.alpha);
    const int colour = d.layout.at(Varying::front_color), second = d.layout.at(Varying::front_secondary);
    typename Types<Arch>::I lanes = filled.lanes;
    for (int p = 0; p < P; ++p) {
      const Batch<Arch> b{fi[p], fj[p], z[p], pass[p], at[p]};
      auto value = [&](int a) { return in.over_w(a, b.fi, b.fj) * cw[p]; };
      lanes += xsimd::select(xsimd::bool_cast(b.pass), decltype(lanes)(1), decltype(lanes)(0));
      const bool all = xsimd::all(b.pass);
      if (d.depth_write) store(planes, 4, b, all, b.z);
      F f;
      if constexpr (Fogged) f = fog_factor(*cx.job.fog, cw[p]);
      // Per channel, the stages SurfaceProgram runs for these settings: the modulate environment
      // (texture_environment_as), the colour sum (clamped), fog, and the opaque blend's clamp (the
      // identity on the colour sum's clamped values, so only after fog).
      for (int k = 0; k < 3; ++k) {
        F x = saturate(modulate(value(colour + k), tex[p][k]) + value(second + k));
        if constexpr (Fogged) x = saturate(f * x + (F(1.0f) - f) * F(cx.job.fog->color[k]));
        store(planes, k, b, all, x);
      }
      store(planes, 3, b, all, saturate(modulate(alpha, tex[p][3])));
    }
    filled.lanes = lanes;
  }
};

// Gouraud, untextured, blended with the mode fixed at compile time (alpha, premultiplied, add),
// clamped, no alpha test (the fragment's alpha is never NaN), no emission, no secondary colour, no
// fog: the stages SurfaceProgram runs for those settings (its colour is the interpolated primary
// colour and the triangle's alpha, then blend), so the same bits, without the branches.
template <class Arch, BlendMode Mode>
struct BlendProgram {
  using F = typename Types<Arch>::F;
  using BF = typename Types<Arch>::BF;
  static constexpr int kAttributes = 3;
  static constexpr bool kClipW = true;
  static int plane(const Draw& d, int a) { return d.layout.at(Varying::front_color) + a; }
  static int attributes(const Draw&) { return 3; }
  const Context<Arch>& cx;
  F alpha;
  FillCounts<Arch> filled;
  explicit BlendProgram(const Context<Arch>& c) : cx(c), alpha(c.t.alpha) {}
  template <bool kFull>
  [[gnu::always_inline]] inline void batch(const Interpolants<Arch, 3>& in, const F& fi, const F& fj, const F& z,
                                           const BF& pass, std::size_t at) {
    const Batch<Arch> b{fi, fj, z, pass, at};
    const bool all = filled.count(b.pass);
    if (cx.d.depth_write) store(cx.planes, 4, b, all, b.z);
    const F inv_w = in.clip_w(b.fi, b.fj);
    const F c[4] = {in.over_w(0, b.fi, b.fj) * inv_w, in.over_w(1, b.fi, b.fj) * inv_w, in.over_w(2, b.fi, b.fj) * inv_w,
                    alpha};
    for (int k = 0; k < 4; ++k) {  // a channel at a time: fewer batches live than all four at once
      const F dst = F::load_unaligned(cx.planes[k] + b.at);
      const F out = blend_channel<Mode>(c[k], alpha, dst, true);  // the plan fuses clamped draws only
      (all ? out : xsimd::select(b.pass, out, dst)).store_unaligned(cx.planes[k] + b.at);
    }
  }
  void end_block(const Interpolants<Arch, 3>&) {}
};

}  // namespace
}  // namespace facet::pixel::simd
