// Internal: the frame plan — what a frame will do, decided before any vertex is touched: the
// checks of the options and the frame's limits, the memory it needs, its draws per pass and, per
// draw, its varyings, pixel program and lighting features. It runs nothing: geometry, lighting,
// set-up, bins and tiles come after it (renderer.cpp, pass.cpp, object_setup.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "facet/render.hpp"
#include "facet/scene.hpp"
#include "frame/pass.hpp"
#include "lighting/setup.hpp"
#include "pixel/program.hpp"
#include "scene/order.hpp"
#include "shadow/map.hpp"
#include "texture/sampler.hpp"

namespace facet::frame {

// Vertices per parallel lighting task and triangles per parallel set-up range. Fixed, so the
// split (and so every bin) is the same for any thread count; small enough that a single object of
// a few thousand triangles spreads over two cores. A range's clipped pieces fit the 16-bit index
// of a bin entry (raster/place.hpp), and at most kMaxRanges ranges fit its other 16 bits.
inline constexpr std::size_t kVertexChunk = 1024;
inline constexpr std::size_t kTriangleRange = 2048;
// A Gouraud chunk with more than this share of its vertices drawn is lit whole, in place (the
// kernel reads the mesh's arrays itself); otherwise only its drawn vertices are, copied through
// their list. A vertex's colour does not depend on which way it was lit: the same bytes.
struct Share {
  std::size_t numerator, denominator;
};
inline constexpr Share kLightWholeChunk{1, 2};
inline constexpr std::size_t kMaxRanges = std::size_t{1} << (32 - raster::kRangeShift);
// Objects at most this large are set up whole by one task, side by side with other such objects.
inline constexpr std::size_t kSmallObjectVertices = 4096;
inline constexpr std::size_t kSmallObjectTriangles = 8192;

inline std::size_t ranges_of(std::size_t triangles) { return (triangles + kTriangleRange - 1) / kTriangleRange; }

// One draw of the frame: a whole object, or one material group of an object drawn with its mesh's
// materials (Instance::mesh_materials). Its triangles [first_triangle, end_triangle) use only the
// vertices [first_vertex, end_vertex), the only ones it transforms and lights.
struct DrawUnit {
  std::uint32_t object = 0, material = 0;
  std::size_t first_triangle = 0, end_triangle = 0, first_vertex = 0, end_vertex = 0;
  // raster::ObjectVertices::only: a double-sided blended object drawn back to front is two draws,
  // its back faces (2) then its front faces (1), as three.js draws it, so that its near side is
  // blended over its far side; 0: one draw of both.
  std::uint8_t only = 0;
  std::size_t triangles() const { return end_triangle - first_triangle; }
  std::size_t vertices() const { return end_vertex - first_vertex; }
  std::size_t ranges() const { return ranges_of(triangles()); }
};

// Which frame this is. A flat or Gouraud frame with shadows is drawn as sub-frames summed per
// pixel (composite.cpp): visibility sub-frames (Phong, plain surfaces, each pixel's visibility of
// up to three shadowed lights as its colour) and parts (the lights, ambient and fog come from
// `lighting`; emission left out when asked). Decided once per frame, before planning.
struct FrameKind {
  enum class Kind : std::uint8_t { whole, visibility, part };
  Kind kind = Kind::whole;
  std::size_t visibility_lights[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX};  // visibility: scene light indices
  const Scene* lighting = nullptr;  // part: its lights, ambient and fog (no meshes)
  bool without_emission = false;    // part: no emission
  bool shadows() const { return kind != Kind::part; }
  bool plain() const { return kind == Kind::visibility; }  // no texture, vertex colour, blending or fog
  const Scene& lights_of(const Scene& scene) const { return lighting ? *lighting : scene; }
};

Status check_options(const RenderOptions& options);
// The frame's set-up ranges and memory against their limits (shared by render and check_render).
Status check_frame_limits(const Scene& scene, const RenderOptions& options, int width, int height);

// Whether some enabled light of the scene casts shadows with `method`.
bool casts_shadows(const Scene& scene, ShadowMethod method);
// World-space boxes of the objects that cast shadows.
void bound_casters(const Scene& scene, shadow::CasterBounds& out);

// The camera's pass: the scene's camera, the options' shading, culling, tile size, depth format
// and clear colour, into `color` (and `depth`).
RenderPass camera_pass(const Scene& scene, const RenderOptions& options, const ImageView& color, const DepthView* depth);
// A colour pass from `camera` (an environment face's, square, 90 degrees), with the scene's faces
// rules and the options' shading, culling, tile size and clear colour.
RenderPass view_pass(const Camera& camera, const Scene& scene, const RenderOptions& options, const ImageView& color,
                     const DepthView* depth);
// A depth-only pass from `view` and `projection` into `depth` (a square shadow-map face).
RenderPass depth_pass(const Eigen::Matrix4d& view, const Eigen::Matrix4d& projection, const DepthView& depth,
                      int tile_size);

// A pass's draws, in object order and, within an object, group order (`units` and `keys` keep
// their capacity): a shadow map's pass draws only the objects that cast shadows, the camera's
// depth pass (and a visibility sub-frame, `depth_writers_only`) only the draws that write depth;
// a colour pass of a back_to_front scene draws its objects in scene_order's order.
void plan_units(const Scene& scene, const RenderPass& p, std::vector<DrawUnit>& units,
                std::vector<scene_order::ObjectKey>& keys, bool depth_writers_only);
bool writes_depth(const Material& m);
// Progress units of a pass with these draws: its tiles, set-up ranges and vertex chunks.
std::uint64_t pass_work(const Scene& scene, const RenderPass& p, std::span<const DrawUnit> draws, bool light_every_vertex);

// Dynamic environments (Environment::dynamic): per scene object the index of its cube (-1: none),
// and six samplers per cube (+X, -X, +Y, -Y, +Z, -Z), filled by the frame's face passes.
struct DynamicCubes {
  std::vector<std::int32_t> of_object;
  std::vector<texture::Sampler> samplers;
};

// Per draw of a pass: its pixel program (varyings, texture, modes), what its lighting takes and
// gives, and whether both of its faces are drawn and lit. Parallel arrays: the tile kernels take
// the programs as one array.
struct PassDraws {
  std::vector<pixel::Draw> programs;
  std::vector<lighting::LightingFeatures> features;
  std::vector<char> two_sided;
  bool any_two_sided() const;
};
// The fog of the frame's pixel programs.
pixel::Fog plan_fog(const Fog& fog);
// The samplers the pixel programs read the scene's textures with, made once per frame
// (make_samplers): `as_made`, one per texture, as the texture says; `clamped`, the same clamped to
// the edge, made only for the textures that environment maps read (the others are left as they
// were).
struct SceneSamplers {
  std::vector<texture::Sampler> as_made, clamped;
};
void make_samplers(const Scene& scene, SceneSamplers& out);
void plan_draws(const Scene& scene, const RenderOptions& options, const RenderPass& p, std::span<const DrawUnit> units,
                const FrameKind& kind, const SceneSamplers& samplers, const DynamicCubes& cubes, PassDraws& out);

}  // namespace facet::frame
