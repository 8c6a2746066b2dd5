// Internal: a render pass — one view of the scene into one set of targets, and everything the
// frame decides once for it: the view and projection, the viewport (with its depth format) and
// its tile grid, the face rules, the shading mode and the clear colour (each draw's varyings and
// pixel program are planned per draw, plan.hpp). A frame is a list of passes run in order
// (frame_plan.hpp); plan.hpp makes each kind (camera_pass, view_pass, depth_pass).
#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "facet/image.hpp"
#include "facet/render.hpp"
#include "facet/scene.hpp"
#include "raster/assemble.hpp"
#include "raster/samples.hpp"

namespace facet::frame {

struct RenderPass {
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d projection = Eigen::Matrix4d::Identity();
  ShadingMode shading = ShadingMode::gouraud;
  std::array<float, 4> clear_color{};
  int tile_size = 64, tiles_x = 0, tiles_y = 0;
  raster::AssemblyFrame assembly;  // viewport, clip planes, cull mode, two-sidedness, tile grid
  // Targets: the caller's views (validated; depth may be null), or, for a depth-only pass, a depth
  // view alone (a shadow map's face).
  const ImageView* color = nullptr;
  const DepthView* depth = nullptr;
  // Depth only (shadow maps): the objects that cast shadows, no lighting, no varying, flat
  // rasterization into the depth target alone; no face is culled.
  bool depth_only = false;
  // Depth only: the objects that cast shadows (a shadow map), or every object that writes depth,
  // as the camera's pass draws them (the camera's depth, for shadow volumes).
  bool casters_only = false;
  // Depth only: per tile, 1 when the target's tile may hold anything but far depth (it persists
  // from frame to frame: a tile no caster reaches is cleared once, not every frame), or null.
  std::uint8_t* depth_dirty = nullptr;
  // An environment face (Environment::dynamic): the object it is seen from is left out, dynamic
  // reflectors are drawn without their reflection, and nothing is shadowed.
  std::uint32_t exclude_object = UINT32_MAX;
  bool environment_face = false;
  // Samples per pixel (RenderOptions::samples): the camera's colour pass only.
  raster::SamplePattern samples{};

  int width() const { return assembly.viewport.width; }
  int height() const { return assembly.viewport.height; }
  bool two_sided() const { return assembly.two_sided; }
  int tile_count() const { return tiles_x * tiles_y; }
};

}  // namespace facet::frame
