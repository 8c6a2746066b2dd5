// Internal: the frame plan — the passes a frame runs, in order, with their targets and what
// follows each, decided before any vertex is touched (plan_frame). The renderer runs it
// (renderer.cpp): build what the passes read (Embree's casters), then for each pass its draws'
// geometry and lighting, set-up and bins (object_setup.cpp), tiles and resolve (pass.cpp), then
// the pass's after-step. A frame that needs none of a kind of pass plans none: a scene without
// shadows or dynamic reflections is the camera's pass alone.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "facet/image.hpp"
#include "facet/render.hpp"
#include "facet/scene.hpp"
#include "frame/pass.hpp"
#include "frame/plan.hpp"
#include "shadow/map.hpp"
#include "shadow/volume.hpp"
#include "tile/kernels.hpp"

namespace facet::frame {

enum class PassKind : std::uint8_t {
  shadow_map_face,   // depth only, from a light, into one face of its shadow map
  volume_depth,      // depth only, the camera's view, for shadow volumes
  environment_face,  // colour, from a dynamic reflector's centre, into one face of its cube
  camera,            // the caller's colour (and depth) views; always last
};
const char* to_string(PassKind kind) noexcept;

// What runs after a pass and before the next.
enum class AfterPass : std::uint8_t {
  nothing,
  build_shadow_volumes,     // the camera's depth is drawn: build the volumes' masks from it
  finish_environment_face,  // the face is drawn: mirror it as GL's cube faces are, make its sampler
};
const char* to_string(AfterPass after) noexcept;

struct PlannedPass {
  PassKind kind = PassKind::camera;
  AfterPass after = AfterPass::nothing;
  RenderPass pass;
  std::uint32_t light = UINT32_MAX;   // shadow_map_face: the scene light
  std::uint32_t object = UINT32_MAX;  // environment_face: the reflecting object (left out of its faces)
  int face = -1;                      // shadow_map_face, environment_face: the face (cube faces +X, -X, +Y, -Y, +Z, -Z)
  int cube = -1;                      // environment_face: the cube (FrameTargets::cube_faces)
};

// A dynamic reflector's six faces, drawn every frame by its face passes.
struct EnvironmentCube {
  std::array<Texture, 6> faces;
  std::array<ImageView, 6> views;
  std::array<bool, 6> mirrored{};
};

// What the planned passes draw into and the frame reads, owned by the renderer and kept from frame
// to frame (a steady frame allocates nothing).
struct FrameTargets {
  // Shadow maps: one per scene light (fitted and drawn when the light has one), the casters' bounds
  // they are fitted to, and the depth views their passes write.
  std::vector<shadow::ShadowMap> maps;
  std::vector<DepthView> map_views;
  shadow::CasterBounds caster_bounds;
  // Shadow volumes: the camera's depth (drawn by a depth-only pass first) and each light's mask.
  shadow::ShadowVolumes volumes;
  DepthView volume_depth;
  // Dynamic environments: per reflector its cube; per object its cube's index and the samplers.
  std::vector<EnvironmentCube> cube_faces;
  DynamicCubes cubes;
};

struct FramePlan {
  std::vector<PlannedPass> passes;  // in the order they run; the camera's last (capacity is kept)
  std::vector<const shadow::ShadowMap*> maps;  // per scene light: its map this frame, or null
  bool raycast = false;  // a light casts ray-cast shadows: Embree's casters are built first
  bool volumes = false;  // shadow volumes: a volume_depth pass builds their masks
  std::uint64_t shadow_map_texels = 0, map_casters = 0, volume_casters = 0;  // for FrameStats
  double seconds_maps = 0;  // fitting the maps
  const PlannedPass& camera() const { return passes.back(); }
  // Some light's map has a face (a light whose casters cannot shade a visible point has none).
  bool any_map() const {
    return std::any_of(maps.begin(), maps.end(), [](const shadow::ShadowMap* m) { return m != nullptr; });
  }
  // One line per pass: its kind, target size, samples, shading, light or object and face, and
  // after-step; then the frame's ray-cast casters, if any.
  std::string describe() const;
};

// Plans a frame of `kind` into `color` (and `depth`): shadow-map faces (light order), the
// camera's depth for shadow volumes, environment faces (object order, +X to -Z), the camera's
// pass. Fits the maps and sizes the targets it needs in `targets`; draws nothing.
void plan_frame(const Scene& scene, const RenderOptions& options, const FrameKind& kind, const ImageView& color,
                const DepthView* depth, const tile::simd::Kernels* kernels, FrameTargets& targets, FramePlan& out);

// After an environment face's pass: its picture mirrored where GL's cube face runs against the
// camera's right, and its sampler made.
void finish_environment_face(FrameTargets& targets, const PlannedPass& p);

}  // namespace facet::frame
