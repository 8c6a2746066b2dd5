// Internal: the pixel program's contract: the plain data a tile rasterizer hands the pixel
// programs (pixel/stages.hpp, pixel/programs_simd.hpp) and the frame plan fills (frame/plan.cpp):
// the tile's memory (TileView), a draw's settings (Draw, PixelProgram, Fog), the Phong sink and a
// tile's job. Plain data only (no Eigen, no standard containers): the programs are compiled once
// per ISA (tile/kernels.hpp) and must not instantiate inline code the linker could merge across
// ISA files (an inline function compiled into files with different ISA flags is merged by the
// linker, and the wider copy may run on a CPU without it).
//
// Tile memory is block-linear: each plane (R, G, B, A, depth) of a size x size tile is stored as
// 8x8 blocks of 64 floats (row-major inside a block, blocks row-major in the tile), so every SIMD
// width (4, 8 or 16 lanes) reads and writes whole contiguous batches, and a block is the unit of
// the hierarchical test: blocks outside a triangle are skipped with three compares, blocks inside
// it skip the edge tests, only blocks on an edge test their pixels.

#pragma once

#include <cstddef>
#include <cstdint>

#include "facet/material.hpp"
#include "facet/render.hpp"
#include "facet/scene.hpp"
#include "raster/triangle_setup.hpp"
#include "raster/varyings.hpp"
#include "io/srgb.hpp"
#include "texture/sampler.hpp"

namespace facet::pixel {

inline constexpr int kBlock = 8;  // block side in pixels
inline constexpr int kBlockPixels = kBlock * kBlock;

// Planes 0..3: colour R, G, B, A; plane 4: depth. `size` is a multiple of kBlock. Blocks are
// cleared lazily: `touched` (one byte per block) says which blocks hold data; the others are
// resolved straight from the clear colour, so a tile that a small triangle grazes costs little.
struct TileView {
  float* plane[5];
  std::uint8_t* touched;
  int size;
  float clear[4];
  const SrgbTable* srgb = nullptr;  // resolve: the table (io/srgb.hpp) that encodes 8-bit output; null: linear
  // The depth format (geometry::DepthFormat): stored depth lies in [depth_lo, depth_far], depth_far
  // is the clear value; a reversed pass's output is the negated stored value.
  float depth_lo = 0.0f, depth_far = 1.0f;
  bool depth_reversed = false;
  // Multisampling (RenderOptions::samples): sample s of tile pixel index p is at p + s *
  // sample_stride in every plane, at offset (sample_x[s], sample_y[s]) from the pixel's corner
  // (raster/samples.hpp); one sample: the pixel centre, stride 0.
  int samples = 1;
  std::size_t sample_stride = 0;
  const std::int32_t* sample_x = nullptr;
  const std::int32_t* sample_y = nullptr;
  // The planes already hold each pixel's clear values (a backdrop, tile/backdrop.hpp): every
  // block counts as touched from the start.
  bool prefilled = false;
};

// The pixel program of one draw (an object with one material), decided by the frame plan
// (frame/plan.cpp). A plain draw (opaque, untextured, no alpha test, no fog, no vertex colours lit
// per pixel) runs the lighting's own program: the flat colour, the interpolated colour, or Phong
// lighting. Any other runs the surface program, GL 2.1's order (pixel/stages.hpp):
//   interpolate -> sample the textures -> texture environment (primary colour and texel) -> add the
//   emission (Material::emission_after_texture) -> add the secondary colour -> fog -> alpha test ->
//   depth test and write -> blend -> store;
// or, for its commonest textured case, the same stages fused with their settings fixed at compile
// time (pixel/programs_simd.hpp: modulate, modulate_fog). The scalar rasterizer runs the stages
// for any surface program.
enum class PixelProgram : std::uint8_t {
  flat, gouraud, phong, surface, surface_textured, modulate, modulate_fog,
  modulate_fixed, modulate_fog_fixed,  // the 16-bit tier (RenderOptions::pixel_precision): fixed-point texels
  blend_alpha, blend_premultiplied, blend_add  // Gouraud, untextured, blended (programs_simd.hpp's BlendProgram)
};
namespace {  // internal linkage: the per-ISA files include this header (see above)
// Whether a draw runs the surface program's stages after its lighting (every program but the
// lighting's own three), whatever the enumerators' order.
constexpr bool runs_surface_stages(PixelProgram p) {
  return p != PixelProgram::flat && p != PixelProgram::gouraud && p != PixelProgram::phong;
}
}  // namespace

struct Draw {
  raster::VaryingLayout layout;  // this draw's varyings (ScreenTriangle::attr and the attribute planes)
  PixelProgram program = PixelProgram::flat;
  const texture::Sampler* texture = nullptr;  // null: untextured
  // The 16-bit tier (RenderOptions::pixel_precision fast): `texture` is sampled by the fixed-point
  // sampler (texture/sampler.hpp: sample_fixed_scalar and its SIMD twin), its bytes read as
  // byte / 255 by the stages that follow. Set for linear (not sRGB) textures only.
  bool fixed_texels = false;
  // The lighting keeps the specular apart (GL's separate specular colour: the texture modulates
  // the rest, the tail adds it back); the plan sets it for textured draws.
  bool separate_specular = false;
  TextureMode texture_env = TextureMode::modulate;
  // The emission is added after the texture environment (the lighting leaves it out):
  // emission_rgb, times the RGB of emission_texture when there is one. False: none (any emission
  // is in the lit colour).
  bool emission = false;
  float emission_rgb[3] = {};
  const texture::Sampler* emission_texture = nullptr;
  // Baked light (Instance::lightmap): read at level 0 at Varying::lightmap_uv, its RGB times
  // lightmap_albedo (the material's diffuse colour times the lightmap's scale), times the texel's
  // RGB on a textured draw (GL_MODULATE), joins the emission (pixel/stages.hpp: lightmap_light).
  // Null: none. A lightmapped draw always has the emission stage.
  const texture::Sampler* lightmap = nullptr;
  float lightmap_albedo[3] = {};
  // Environment mapping (Material::environment; pixel/stages.hpp): the maps clamped to the edge
  // (sphere and normal: environment_map[0]; cube: the faces +X, -X, +Y, -Y, +Z, -Z). Flat and
  // Gouraud draws carry the vertices' generated coordinates in Varying::environment; Phong draws
  // generate them per pixel.
  EnvironmentMode environment = EnvironmentMode::none;
  EnvironmentBlend environment_blend = EnvironmentBlend::add;
  float environment_strength = 1.0f;
  const texture::Sampler* environment_map[6] = {};
  float environment_to_world[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // cube: eye to world rotation, row-major
  // A tangent-space normal map (Material::normal_texture), lit per pixel: pixel_normal perturbs the
  // interpolated normal in the frame of Varying::tangent. Null: none.
  const texture::Sampler* normal_map = nullptr;
  float normal_scale = 1.0f;
  // An occlusion map (Material::occlusion_texture), lit per pixel: its red channel r gives the
  // pixel's ambient occlusion 1 + strength (r - 1), which the lighting multiplies every ambient
  // term by. Null: none.
  const texture::Sampler* occlusion_map = nullptr;
  float occlusion_strength = 1.0f;
  // A PBR draw's metallic-roughness map (per pixel): its blue and green channels go to the
  // lighting, which multiplies them by the material's factors.
  const texture::Sampler* metal_rough_map = nullptr;
  // A height map (Material::bump_texture): its red channel's differences over one level-0 texel
  // (bump_du, bump_dv in texture coordinates) tilt the per-pixel normal (pixel_normal) or, in flat
  // and Gouraud draws with a 2D environment map, move the environment's coordinates. Null: none.
  const texture::Sampler* bump_map = nullptr;
  float bump_scale = 1.0f;
  float bump_du = 0.0f, bump_dv = 0.0f;
  float uv_scale[2] = {1.0f, 1.0f};
  float alpha_cutoff = 0.0f;  // alpha test: the fragment is kept when alpha >= cutoff (0: every fragment)
  // Alpha to coverage (multisampled draws only): sample s of N keeps its coverage when alpha > s / N
  // (alpha_to_coverage_passes).
  bool alpha_to_coverage = false;
  BlendMode blend = BlendMode::opaque;
  bool depth_write = true;
  bool clamp = true;  // blend results saturate to [0, 1]; false (HDR float output): only below at 0
};

// Fog on the eye-space depth z = -z_eye = clip w (exact for facet's perspective projection: the
// rasterizer interpolates 1/w, so z = 1 / (1/w) at each pixel). Factor f in [0, 1], 1 = no fog:
//   linear f = (end - z) / (end - start)  (end == start: f = 1 for z < end, 0 beyond: a step);
//   exp    f = e^(-density z);   exp2  f = e^(-(density z)^2);
// colour = f colour + (1 - f) fog colour; alpha unchanged.
struct Fog {
  FogMode mode = FogMode::none;
  float color[3] = {};
  float start = 0.0f, end = 1.0f, density = 1.0f;
  float scale = 1.0f;  // linear: 1 / (end - start), 0 when end == start
};

// Per-pixel (Phong) lighting: the kernel gathers the interpolated eye-space positions and normals
// of visible pixels into these structure-of-arrays buffers (capacity kPhongCapacity), then asks
// `shade` to light them with the shader of `object`; the colours come back in r, g, b. Surface
// draws also gather the albedo (vertex colours) and get the secondary colour back, and carry the
// inputs of their program's tail computed before lighting (pixel/stages.hpp: carry) in `carry`.
inline constexpr int kPhongCapacity = 256;  // a multiple of the widest batch (16)
inline constexpr int kMaxCarried = 8;
inline constexpr int kPhongStreams = 18 + kMaxCarried;
struct PhongSink {
  float *px, *py, *pz, *nx, *ny, *nz, *r, *g, *b;
  float *ar, *ag, *ab, *sr, *sg, *sb;  // albedo in, secondary out
  float* ao;                           // ambient occlusion in (a draw with an occlusion map)
  float *pm, *pr;                      // metallic and roughness texels in (a PBR draw with their map)
  float* carry[kMaxCarried];
  std::uint32_t* pixel;  // tile-buffer index of each entry
  // Multisampled tiles: each entry's samples (bit s: the pixel's sample s, at pixel + s x the
  // tile's sample stride; a program run per sample gathers bit 0 at the sample's own index); null
  // for one sample.
  std::uint32_t* samples;
  void* context;
  // `padded` is `count` rounded up to 16; entries [count, padded) hold zeros.
  void (*shade)(void* context, std::uint32_t object, std::size_t count, std::size_t padded);
};

struct TileJob {
  ShadingMode shading;
  const raster::ScreenTriangle* const* ranges;  // set-up ranges; a bin entry is (range << 16) | index
  const std::uint32_t* bin;
  std::size_t bin_size;
  int x0, y0, x1, y1;  // the tile's pixels in the image, [x0, x1) x [y0, y1)
  PhongSink* phong;  // for ShadingMode::phong
  const Draw* draws;  // per ScreenTriangle::object
  const Fog* fog;
};

struct TileCounters {
  std::uint64_t tested = 0, filled = 0;
};

}  // namespace facet::pixel
