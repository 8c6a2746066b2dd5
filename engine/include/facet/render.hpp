// Rendering a scene into a caller's image: transform, clip, bin into screen tiles, rasterize with
// integer edge functions (top-left rule), depth-test, shade (flat / Gouraud / Phong) and resolve
// into the caller's ImageView. See README "Rasterization" for the exact rules.
//
// Ownership and threads. A Renderer owns its scratch memory (reused from frame to frame, so a
// repeated frame allocates nothing) and its worker threads (its own tbb::task_arena, capped by
// RenderOptions::threads; process-wide TBB settings are never touched). One Renderer renders one
// frame at a time: do not call render() on the same Renderer from two threads at once. Different
// Renderers share nothing and may render at the same time from different threads, also the same
// Scene (a render only reads the scene). The library has no global state and reads no
// environment variables.
//
// Scenes belong to the caller and are read only during render(). Between frames anything in them
// may change: move the camera, edit materials and lights, or change mesh positions in place (keep
// the vertex count and the index ranges valid; recompute normals with compute_vertex_normals if
// the shape changed). Every render validates the scene it is given, so nothing is cached across
// frames but memory.
//
// Conventions: right-handed world; the camera looks down -z in eye space (gluLookAt); clip space
// and projection as gluPerspective; window depth 0 at the near plane, 1 at the far plane, test
// LESS; images row 0 at the top unless the view is y_up; counter-clockwise faces are front faces.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>

#include "facet/image.hpp"
#include "facet/lighting.hpp"
#include "facet/scene.hpp"
#include "facet/status.hpp"

namespace facet {

enum class ShadingMode {
  flat,     // one lighting evaluation per triangle: face normal at the centroid
  gouraud,  // per-vertex lighting, colours interpolated (perspective-correct)
  phong,    // position and normal interpolated, normal renormalised, lit per pixel
};
enum class CullMode { none, back, front };
// How the camera's pass stores depth. gl: window depth 0.5 z/w + 0.5 in a float, as GL's default
// (and as llvmpipe, which facet's images are compared with): exact near the camera, but a float
// holds 24 bits below 1, so with near / far ranges like 0.05 / 1e6 distant surfaces z-fight, and
// beyond about 1.6e7 x near (an infinite projection) depth rounds to the far value and nothing is
// drawn. reversed: -near / w in a float (reversed-Z: the same relative precision at every
// distance). automatic: reversed when the camera's far plane is infinite or more than 1e5 times its
// near plane, gl otherwise. Images differ only where depth decides a different surface.
enum class DepthMode { automatic, gl, reversed };
const char* to_string(DepthMode mode) noexcept;
// The mode a frame of `camera` uses: `mode`, or for automatic gl or reversed by the rule above.
DepthMode depth_mode_for(const Camera& camera, DepthMode mode) noexcept;

const char* to_string(ShadingMode mode) noexcept;

// The number format of textured pixels (docs/rasterization.md, "Pixel precision"), a speed against
// accuracy choice like PowTier. exact: the float programs (every sample within a step of the
// double reference sampler). fast: the 16-bit tier, texels filtered in fixed point as llvmpipe does
// (texture::sample_fixed_scalar's contract: bilinear within 1.5 steps of the reference, mean 0.35;
// trilinear 2 and 0.35; nearest exact) for every draw's linear (not sRGB) diffuse texture, in any
// shading mode, texture environment, blend mode, fog and alpha test, multisampled or not; sRGB
// textures and the other maps (emission, normal, bump, occlusion, environment, lightmaps) stay
// exact. automatic (the default): the fast tier where it is both within its contract and faster;
// today it is within its contract but not faster (docs/rasterization.md), so automatic is the
// exact tier. Both paths: the scalar path's fixed-point sampler is the SIMD one's twin (the same
// bytes). Images are byte-identical for any thread count in either tier.
enum class PixelPrecision { automatic, exact, fast };
const char* to_string(PixelPrecision precision) noexcept;

struct RenderOptions {
  ShadingMode shading = ShadingMode::gouraud;
  LightingPath path = LightingPath::simd;
  Isa isa = Isa::best;                    // simd path only; an ISA the CPU lacks is an error
  PowTier pow_tier = PowTier::automatic;  // simd path only
  PixelPrecision pixel_precision = PixelPrecision::automatic;
  // Faces wind counter-clockwise seen from the front. In a two-sided scene back faces are never
  // culled by CullMode::back: they are drawn with their back-side lighting.
  CullMode cull = CullMode::back;
  int tile_size = 64;  // pixels; 8..256, a multiple of 8
  // Multisampling (GL's MSAA): 1, 4, 8 or 16 samples per pixel at the standard positions (4: the
  // pattern of Direct3D, Vulkan and llvmpipe). Coverage and depth are per sample; each pixel is
  // shaded once, at its centre, for the samples a triangle covers; blending is per sample; the
  // samples are averaged in linear colour before the output's conversion (sRGB encoding
  // included). Shadow maps, ray-cast and volume shadows are looked up per pixel (at the shaded
  // point); the depth view holds each pixel's nearest sample. Tile memory grows N-fold. The
  // simd path's fused programs give way to the general ones (the same bytes), so multisampled
  // frames draw the 16-bit pixel tier's draws exact.
  int samples = 1;
  // Worker threads of this renderer (its own tbb::task_arena; process-wide TBB settings are
  // never touched): 0 = all cores, otherwise 1..256. The image is byte-identical for any value.
  // More than TBB's process-wide limit (by default the hardware threads) runs that many:
  // FrameStats::threads reports what ran.
  int threads = 0;
  std::array<float, 4> clear_color{0.0f, 0.0f, 0.0f, 1.0f};
  bool hdr = false;  // RGBA32F output keeps unclamped (>= 0) lighting; 8-bit output is always clamped
  // 8-bit output encodes the linear colour with the sRGB transfer function (as GL_FRAMEBUFFER_SRGB),
  // exactly: each channel is the correctly rounded 8-bit value, so that a picture looks as bright
  // as the light it shows (the default, as every viewer and image file expects). Alpha and float
  // output stay linear. False writes the lit values as they are (GL 2.1's framebuffer, what the
  // llvmpipe comparisons ask for; `facet render --linear`).
  bool srgb = true;
  bool cull_lights = true;  // the frame plan's per-object light culling (LightingOptions::cull_lights)
  // The camera pass's depth format. The depth image (render's `depth`) holds window depth (0 near,
  // 1 far) for gl, and near / w (1 at the near plane, 0 at infinity) for reversed.
  DepthMode depth = DepthMode::automatic;
  // Gouraud lights only the vertices of triangles that can be drawn (not culled, degenerate,
  // non-finite or outside the frustum), flat only those triangles; true lights every vertex (or
  // triangle). The image is the same bytes either way (FrameStats::vertices_skipped counts the
  // difference); true is for measurements.
  bool light_every_vertex = false;
  // Gouraud with normal and bump maps: false (GL's fixed function, the default) lights the vertex
  // normals and ignores the maps; true lights each vertex with its normal perturbed by them, read
  // at the vertex's texture coordinates at the one mipmap level whose texels are about the size of
  // the mesh's triangles (docs/relief.md, "Per-vertex relief"). Flat shading ignores the maps
  // either way; Phong applies them per pixel either way.
  bool vertex_relief = false;
  // The most memory one frame may take in the renderer's own scratch (transformed vertices,
  // triangle records, bins, per-thread tiles; not the caller's scene or image), estimated from
  // the scene before anything is allocated (estimate_frame_bytes). A frame over it is refused with
  // ErrorCode::out_of_memory before any pixel is written. 0 = no limit. `facet render
  // --memory-budget-mb` sets it.
  std::uint64_t memory_budget_bytes = std::uint64_t{4} << 30;
  // Progress and cancellation, for long frames: called with the share of the frame's work done
  // so far (an estimate in [0, 1] that only grows), after each vertex chunk, set-up range and tile.
  // Return false to cancel: render() then stops at the next chunk or tile and returns
  // ErrorCode::cancelled. A frame cancelled before its tiles started has written no pixel; one
  // cancelled later leaves the image partly written. Called from the renderer's worker threads,
  // one call at a time (never concurrently); it must not call into the same Renderer.
  std::function<bool(double done)> progress;
};

struct FrameStats {
  std::uint64_t triangles_in = 0;         // triangles of all objects
  std::uint64_t triangles_nonfinite = 0;  // dropped: NaN/Inf clip coordinates, or a piece whose projection overflows
  std::uint64_t triangles_outside = 0;    // dropped: entirely outside one frustum plane
  std::uint64_t triangles_clipped = 0;    // crossed the near/far plane or the guard band
  std::uint64_t triangles_culled = 0;     // facing away (after clipping, per piece)
  std::uint64_t triangles_degenerate = 0; // zero area after snapping to 1/256 pixel
  std::uint64_t triangles_small = 0;      // no pixel centre of the viewport within their bounds
  std::uint64_t triangles_drawn = 0;      // pieces set up and binned
  std::uint64_t bin_entries = 0;          // (triangle, tile) pairs
  std::uint64_t vertices_lit = 0;         // lighting evaluations: vertices, centroids or pixels
  std::uint64_t vertices_skipped = 0;     // not lit: vertices (Gouraud) no drawable triangle uses, or
                                          // triangles (flat) that cannot be drawn
  std::uint64_t vertex_lights_evaluated = 0;  // (evaluation, light) pairs computed
  std::uint64_t vertex_lights_skipped = 0;    // pairs the frame plan skipped (lights culled per object)
  std::uint64_t pixels_tested = 0;        // covered pixels that were depth-tested
  std::uint64_t pixels_filled = 0;        // pixels that passed and were written
  // Per-object set-up, summed over objects: objects small enough to be set up side by side (one
  // task each) add their thread time, so with several threads these can exceed the frame time.
  double seconds_lighting = 0;  // per-object set-up: clip transform, vertex (Gouraud) or centroid (flat) lighting
  double seconds_geometry = 0;  // transform, clip, project, set up, bin
  double seconds_raster = 0;    // wall time of the tile loop: coverage, depth, shading, resolve (all threads)
  double seconds_resolve = 0;   // of which resolving tiles into the caller's image, summed over threads
  // Shadows: building the casters' ray-cast hierarchy, and fitting and drawing the shadow maps
  // (their depth-only passes); the lookups are part of the lighting of pixels (seconds_raster).
  double seconds_shadows = 0;
  double seconds_environment = 0;  // preparing PBR materials' surroundings (DFG table, harmonics, prefiltered cube)
  std::uint64_t shadow_casters = 0;     // triangles that can cast shadows (ray-cast shadows, shadow maps)
  std::uint64_t shadow_map_texels = 0;  // texels of the frame's shadow maps (every face)
  std::uint64_t shadow_map_pixels = 0;  // of which written by casters (depth test passed)
  // The exposure the frame used (Scene::display: its ev, or the metered one); 0 for GL's display.
  float exposure_ev = 0;
  int threads = 0;              // worker threads the frame really had (the request, capped; see RenderOptions)
  double seconds_total = 0;
};

// Checks options on their own (what render() checks before touching anything): the ranges above,
// and that options.isa exists on this CPU when options.path is simd.
Status check_render_options(const RenderOptions& options) noexcept;

// Everything render() checks before it allocates or writes anything, without rendering: the
// scene (validate_scene), the options, the frame's limit on set-up ranges (each object takes one
// range per 2048 triangles, at least one if it has any; a frame holds at most 65536 ranges, so at
// most 65536 objects and 134,217,728 triangles) and the memory estimate against
// options.memory_budget_bytes, for a width x height image. `facet check` calls it too.
Status check_render(const Scene& scene, const RenderOptions& options, int width, int height) noexcept;

// The renderer's scratch memory for one frame of `scene` (an upper estimate for unclipped
// geometry): what RenderOptions::memory_budget_bytes is compared with.
std::uint64_t estimate_frame_bytes(const Scene& scene, const RenderOptions& options, int width, int height) noexcept;

class Renderer {
 public:
  Renderer();  // configured with RenderOptions{}
  // A renderer with a configuration (threads, ISA, path, tile size, pow tier, shading, culling…)
  // that render(scene, color, …) uses. Check it first with check_render_options, or let the first
  // render report it.
  explicit Renderer(const RenderOptions& config);
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  const RenderOptions& config() const noexcept;
  void set_config(const RenderOptions& config) noexcept;

  // Renders with the renderer's configuration.
  Status render(const Scene& scene, const ImageView& color, const DepthView* depth = nullptr,
                FrameStats* stats = nullptr) noexcept;

  // What the last successful render did (counters and per-stage times); zero before the first.
  FrameStats last_stats() const noexcept;

  // Renders `scene` into `color` (and `depth`, if given, of the same size). Validates the scene,
  // the options and the views first: on error nothing is written. Never throws.
  Status render(const Scene& scene, const RenderOptions& options, const ImageView& color,
                const DepthView* depth = nullptr, FrameStats* stats = nullptr) noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facet
