// The frame's public checks and names (facet/render.hpp): the options' check, the memory
// estimate a frame is checked against before anything is allocated, check_render, and the
// to_string of the render options' enums. Planning itself is in plan.cpp and frame_plan.cpp.
#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/info.h>

#include "common/format.hpp"
#include "common/parallel.hpp"
#include "frame/plan.hpp"
#include "lighting/image_light.hpp"
#include "lighting/point_shader.hpp"
#include "raster/triangle_setup.hpp"
#include "scene/validate.hpp"
#include "shadow/volume.hpp"

namespace facet {

const char* to_string(ShadingMode mode) noexcept {
  switch (mode) {
    case ShadingMode::flat: return "flat";
    case ShadingMode::gouraud: return "gouraud";
    case ShadingMode::phong: return "phong";
  }
  return "unknown";
}

const char* to_string(PixelPrecision precision) noexcept {
  switch (precision) {
    case PixelPrecision::automatic: return "auto";
    case PixelPrecision::exact: return "exact";
    case PixelPrecision::fast: return "fast";
  }
  return "unknown";
}

DepthMode depth_mode_for(const Camera& camera, DepthMode mode) noexcept {
  if (mode != DepthMode::automatic) return mode;
  if (camera.projection == Projection::orthographic) return DepthMode::gl;  // linear depth: no need
  const bool reversed = !std::isfinite(camera.far) || double(camera.far) > 1e5 * double(camera.near);
  return reversed ? DepthMode::reversed : DepthMode::gl;
}

const char* to_string(DepthMode mode) noexcept {
  switch (mode) {
    case DepthMode::automatic: return "auto";
    case DepthMode::gl: return "gl";
    case DepthMode::reversed: return "reversed";
  }
  return "unknown";
}

Status check_render_options(const RenderOptions& options) noexcept {
  try {
    return frame::check_options(options);
  } catch (const std::exception&) {
    return {ErrorCode::out_of_memory, "options", "out of memory while checking the options"};
  }
}

std::uint64_t estimate_frame_bytes(const Scene& scene, const RenderOptions& options, int width, int height) noexcept {
  using U = std::uint64_t;
  const auto sat_add = [](U a, U b) { return a > ~U{0} - b ? ~U{0} : a + b; };
  const auto sat_mul = [](U a, U b) { return b != 0 && a > ~U{0} / b ? ~U{0} : a * b; };
  // Per vertex: clip position, screen vertex, front and back colour, eye position and normal
  // (and with vertex_relief the perturbed normal).
  const U per_vertex = 16 + 24 + 2 * 12 + 2 * 12 + (options.vertex_relief ? 12 : 0);
  // Per triangle: its record, its entry between the set-up's two phases (4 + 1 bytes) and its
  // bin entries (one tile each, for unclipped small triangles); for flat shading also its
  // centroid, face normal and two colours (4 x 12 bytes).
  U bytes = 0, max_vertices = 0, max_triangles = 0;
  for (const Instance& inst : scene.objects) {
    if (inst.mesh >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    // A double-sided blended object is drawn twice (its faces apart): its records twice over.
    const U draws = (inst.double_sided || scene.two_sided) && is_transparent(scene, inst) ? 2 : 1;
    bytes = sat_add(bytes, sat_mul(draws * mesh.triangle_count(), sizeof(raster::ScreenTriangle) + 5 + 3 * 4));
    max_vertices = std::max<U>(max_vertices, mesh.vertex_count());
    max_triangles = std::max<U>(max_triangles, mesh.triangle_count());
  }
  const U slots = static_cast<U>(
      parallel::usable_threads(options.threads > 0 ? std::min(options.threads, 256) : tbb::info::default_concurrency()));
  // Slot 0 holds the largest object; the others at most a small object each.
  bytes = sat_add(bytes, sat_add(sat_mul(max_vertices, per_vertex), sat_mul(max_triangles, 4 * 12)));
  bytes = sat_add(bytes, sat_mul(slots, frame::kSmallObjectVertices * per_vertex + frame::kSmallObjectTriangles * 4 * 12));
  // Per object: its shader's copy of the lights.
  bytes = sat_add(bytes, sat_mul(sat_mul(scene.objects.size(), scene.lights.size()), 512));
  // Per thread: tile planes and SoA lighting scratch; per tile: its bin.
  const U tile = static_cast<U>(std::clamp(options.tile_size, 8, 256));
  const U samples = static_cast<U>(std::clamp(options.samples, 1, 16));
  bytes = sat_add(bytes, sat_mul(slots, 5 * (samples * (tile * tile + 64) + 64) * 4 + 64 * 1024));
  const U tiles = (static_cast<U>(std::max(width, 1)) / tile + 1) * (static_cast<U>(std::max(height, 1)) / tile + 1);
  bytes = sat_add(bytes, sat_mul(tiles, 64));
  // Ray-cast shadows: Embree's copy of the casters (12 bytes a vertex and a triangle's indices)
  // and its hierarchy (allowed 96 bytes a triangle), and the per-thread visibility scratch.
  const bool raycast = frame::casts_shadows(scene, ShadowMethod::raycast);
  if (raycast) {
    for (const Instance& inst : scene.objects) {
      if (inst.mesh >= scene.meshes.size() || !inst.cast_shadows) continue;
      const Mesh& mesh = scene.meshes[inst.mesh].mesh;
      bytes = sat_add(bytes, sat_add(sat_mul(mesh.vertex_count(), 12), sat_mul(mesh.triangle_count(), 12 + 96)));
    }
  }
  // Shadow maps: their depth images (every face) and their passes' bins; and the per-thread
  // visibility scratch of every shadowed light.
  bool maps = false;
  for (const Light& l : scene.lights) {
    if (!l.enabled || l.shadow.method != ShadowMethod::map) continue;
    maps = true;
    const U texels = static_cast<U>(shadow::ShadowMap::bytes(l)) / 4;
    bytes = sat_add(bytes, sat_add(texels * 4, (texels / (tile * tile) + 6) * 64));
  }
  // Shadow volumes: the camera's depth, the masks, the volumes' triangles, the casters' adjacency.
  std::size_t volume_lights = 0, casters = 0;
  for (const Light& l : scene.lights) volume_lights += l.enabled && l.shadow.method == ShadowMethod::volume;
  if (volume_lights > 0) {
    for (const Instance& inst : scene.objects) {
      if (inst.mesh < scene.meshes.size() && inst.cast_shadows) casters += scene.meshes[inst.mesh].mesh.triangle_count();
    }
    bytes = sat_add(bytes, shadow::ShadowVolumes::bytes(width, height, volume_lights, casters));
  }
  // Flat and Gouraud shadows: three float frames and a visibility per shadowed light
  // (render_composite).
  std::size_t shadowed = 0;
  for (const Light& l : scene.lights) shadowed += l.enabled && l.shadow.method != ShadowMethod::none;
  if (shadowed > 0 && options.shading != ShadingMode::phong) {
    const U pixels = static_cast<U>(std::max(width, 1)) * static_cast<U>(std::max(height, 1));
    bytes = sat_add(bytes, sat_mul(pixels, 3 * 16 + 4 * U(shadowed)));
  }
  if (raycast || maps || volume_lights > 0) {
    bytes = sat_add(bytes, sat_mul(slots, U(kMaxShadowedLights) * (frame::kVertexChunk + frame::kTriangleRange) * 8));
  }
  // A display transform (Scene::display) or a backdrop: the frame in floats and its depth
  // (render_display).
  if (!scene.display.identity() || scene.background == Background::environment) {
    bytes = sat_add(bytes, sat_mul(static_cast<U>(std::max(width, 1)) * static_cast<U>(std::max(height, 1)), 20));
  }
  // The surroundings of PBR materials and of the backdrop, prepared once and kept by the
  // renderer (lighting/image_light.hpp).
  const bool pbr = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.model == MaterialModel::pbr; });
  const bool surroundings = pbr || scene.background == Background::environment;
  if (surroundings) {
    bytes = sat_add(bytes, lighting::ImageLight::estimate_bytes(scene.environment_light));
  }
  // Dynamic environments: six RGBA8 faces per reflecting object, and their passes' bins.
  for (const Instance& inst : scene.objects) {
    if (inst.material >= scene.materials.size()) continue;
    const Environment& e = scene.materials[inst.material].environment;
    if (inst.mesh_materials || !e.dynamic) continue;
    const U side = static_cast<U>(std::clamp(e.resolution, 1, 4096));
    bytes = sat_add(bytes, 6 * (side * side * 4 + (side / tile + 1) * (side / tile + 1) * 64));
  }
  return bytes;
}

Status check_render(const Scene& scene, const RenderOptions& options, int width, int height) noexcept {
  try {
    if (width < 1 || height < 1 || width > kMaxImageDimension || height > kMaxImageDimension) {
      return {ErrorCode::invalid_argument, "image",
              "image: expected a size of 1.." + std::to_string(kMaxImageDimension) + " per side"};
    }
    if (Status s = frame::check_options(options); !s.ok()) return s;
    if (Status s = validate_scene(scene); !s.ok()) return s;
    if (scene.camera.projection == Projection::orthographic) {
      // Reversed depth stores near / w and fog reads eye depth as clip w: both constant (w = 1) in
      // a box, so neither has a meaning there.
      if (options.depth == DepthMode::reversed) {
        return {ErrorCode::unsupported, "options.depth",
                "options.depth: reversed depth needs a perspective camera (an orthographic one stores depth linearly: "
                "use \"gl\" or \"auto\")"};
      }
      if (scene.fog.mode != FogMode::none) {
        return {ErrorCode::unsupported, "fog.mode", "fog.mode: fog needs a perspective camera (it reads eye depth from clip w)"};
      }
    }
    // Flat and Gouraud shadows sum sub-frames per pixel (render_composite): only for materials
    // whose colour is linear in the lighting.
    const bool shadowed = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
      return l.enabled && l.shadow.method != ShadowMethod::none;
    });
    if (shadowed && options.shading != ShadingMode::phong) {
      for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& mat = scene.materials[m];
        const bool textured = mat.diffuse_texture != kNoTexture;
        const std::string field = "materials[" + std::to_string(m) + "]";
        if (textured && mat.texture_mode != TextureMode::modulate) {
          return {ErrorCode::unsupported, field + ".texture_mode",
                  field + ".texture_mode: with shadows in flat or Gouraud shading, textures modulate the lighting "
                          "(\"modulate\"), or draw in Phong shading (--shading phong)"};
        }
        if (mat.blend != BlendMode::opaque && mat.blend != BlendMode::alpha && mat.blend != BlendMode::premultiplied) {
          return {ErrorCode::unsupported, field + ".blend",
                  field + ".blend: with shadows in flat or Gouraud shading, blending is opaque, alpha or "
                          "premultiplied, or draw in Phong shading (--shading phong)"};
        }
      }
    }
    return frame::check_frame_limits(scene, options, width, height);
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "scene", "out of memory while checking the scene"};
  }
}

}  // namespace facet

namespace facet::frame {

Status check_options(const RenderOptions& o) {
  auto bad = [](const char* field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, field, std::string(field) + ": " + what};
  };
  if (o.shading != ShadingMode::flat && o.shading != ShadingMode::gouraud && o.shading != ShadingMode::phong) {
    return bad("options.shading", "unknown shading mode");
  }
  if (o.path != LightingPath::reference && o.path != LightingPath::scalar && o.path != LightingPath::simd) {
    return bad("options.path", "unknown lighting path");
  }
  if (o.isa != Isa::best && o.isa != Isa::sse2 && o.isa != Isa::avx2 && o.isa != Isa::avx512) {
    return bad("options.isa", "unknown instruction set");
  }
  if (o.pow_tier != PowTier::automatic && o.pow_tier != PowTier::exact && o.pow_tier != PowTier::fast &&
      o.pow_tier != PowTier::integer && o.pow_tier != PowTier::schlick) {
    return bad("options.pow_tier", "unknown pow tier");
  }
  if (o.path == LightingPath::simd && !isa_supported(o.isa)) {
    return {ErrorCode::unsupported, "options.isa",
            std::string("options.isa: this CPU has no ") + to_string(o.isa) + " (best available: " +
                to_string(best_isa()) + ")"};
  }
  if (o.cull != CullMode::none && o.cull != CullMode::back && o.cull != CullMode::front) {
    return bad("options.cull", "unknown cull mode");
  }
  if (o.depth != DepthMode::automatic && o.depth != DepthMode::gl && o.depth != DepthMode::reversed) {
    return bad("options.depth", "unknown depth mode");
  }
  if (o.tile_size < 8 || o.tile_size > 256 || o.tile_size % 8 != 0) {
    return bad("options.tile_size", "expected a multiple of 8 in [8, 256], found " + std::to_string(o.tile_size));
  }
  if (o.samples != 1 && o.samples != 4 && o.samples != 8 && o.samples != 16) {
    return bad("options.samples", "expected 1, 4, 8 or 16 samples per pixel, found " + std::to_string(o.samples));
  }
  if (o.threads < 0 || o.threads > 256) {
    return bad("options.threads", "expected 0 (all cores) or 1..256, found " + std::to_string(o.threads));
  }
  for (float c : o.clear_color) {
    if (!std::isfinite(c)) return bad("options.clear_color", "expected finite components");
  }
  return {};
}

}  // namespace facet::frame
