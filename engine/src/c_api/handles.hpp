// Internal: the C API's handles and the helpers its entry points share (c_api.cpp: defaults,
// renderers and rendering; c_api_scene.cpp: building and editing scenes, loading files, framing;
// c_api_textures.cpp: vertex data and textures).
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <tuple>
#include <string>
#include <type_traits>
#include <vector>

#include "facet/facet.h"
#include "common/format.hpp"
#include "facet/facet.hpp"

struct facet_renderer {
  facet::Renderer renderer;
  std::string error;
};

struct facet_scene {
  facet::Scene scene;
  mutable std::string error;  // the last call's message: set by the calls that read a scene too
  std::string warnings;  // of the last facet_scene_load_file
  facet::AssetAccess assets;  // what facet_scene_load_file may read
  std::string load_camera;    // facet_scene_set_load_camera: ModelOptions::camera
  std::string cameras;        // of the last facet_scene_load_file: Model::cameras, one a line
  // Stable ids: object_ids[i] / light_ids[i] is the id of scene.objects[i] / scene.lights[i]
  // (ids are handed out in order and never reused, so they equal the index until one is removed).
  std::vector<std::uint32_t> object_ids, light_ids;
  std::uint32_t next_object_id = 0, next_light_id = 0;
  std::vector<char> material_removed;  // one per scene.materials entry
  // Cube faces made from an equirectangular texture: (texture id, face size, encoding) -> the
  // first face's id, so that asking again costs nothing.
  std::map<std::tuple<std::uint32_t, int, int>, std::uint32_t> equirect_faces;
  // The last loaded model's motion (facet/animation.hpp): what facet_scene_pose reads. Dropped
  // when an object or light the model placed is removed (their indices no longer match).
  std::shared_ptr<const facet::Rig> rig;
  facet::MotionInfo motion;
  bool file_camera = false;

  // The index of an object or light id, or SIZE_MAX.
  static std::size_t index_of(const std::vector<std::uint32_t>& ids, std::uint32_t id) {
    const auto it = std::lower_bound(ids.begin(), ids.end(), id);  // ids stay sorted: appended in order, erased in place
    return it != ids.end() && *it == id ? static_cast<std::size_t>(it - ids.begin()) : SIZE_MAX;
  }
  void reset_ids() {
    object_ids.resize(scene.objects.size());
    for (std::size_t i = 0; i < object_ids.size(); ++i) object_ids[i] = static_cast<std::uint32_t>(i);
    light_ids.resize(scene.lights.size());
    for (std::size_t i = 0; i < light_ids.size(); ++i) light_ids[i] = static_cast<std::uint32_t>(i);
    next_object_id = static_cast<std::uint32_t>(object_ids.size());
    next_light_id = static_cast<std::uint32_t>(light_ids.size());
    material_removed.assign(scene.materials.size(), 0);
    equirect_faces.clear();
  }
};

namespace facet::c_api {


inline facet_status to_c(facet::ErrorCode code) {
  switch (code) {
    case facet::ErrorCode::ok: return FACET_OK;
    case facet::ErrorCode::invalid_argument: return FACET_INVALID_ARGUMENT;
    case facet::ErrorCode::parse_error: return FACET_PARSE_ERROR;
    case facet::ErrorCode::io_error: return FACET_IO_ERROR;
    case facet::ErrorCode::unsupported: return FACET_UNSUPPORTED;
    case facet::ErrorCode::out_of_memory: return FACET_OUT_OF_MEMORY;
    case facet::ErrorCode::cancelled: return FACET_CANCELLED;
  }
  return FACET_INVALID_ARGUMENT;
}

// Records the outcome in `error` ("" on success) and returns its C status.
inline facet_status report(std::string& error, const facet::Status& s) {
  error = s.ok() ? std::string() : s.message();
  return to_c(s.code());
}

inline facet_status fail(std::string& error, const char* field, const std::string& what) {
  error = std::string(field) + ": " + what;
  return FACET_INVALID_ARGUMENT;
}

inline facet::Vec3 vec3(const float* v) { return {v[0], v[1], v[2]}; }

// A C enum as the integer the caller stored. C lets a caller put any int in an enum object; in
// C++ loading a value outside the enumerators' range is undefined (UBSan: -fsanitize=enum), so
// enums that come from C are read through their bytes and range-checked as integers.
template <class E>
inline long raw(const E& e) {
  std::underlying_type_t<E> v;
  static_assert(sizeof v == sizeof e);
  std::memcpy(&v, &e, sizeof v);
  return static_cast<long>(v);
}

// A facet_up as facet::UpAxis (their orders agree); false for any other value.
inline bool up_axis(const facet_up& up, facet::UpAxis& out) {
  const long v = raw(up);
  if (v < FACET_UP_Y || v > FACET_UP_NEG_Z) return false;
  static_assert(int(facet::UpAxis::neg_z) == FACET_UP_NEG_Z && int(facet::UpAxis::x) == FACET_UP_X);
  out = static_cast<facet::UpAxis>(v);
  return true;
}

// Runs `fn` (returning facet_status), turning std::bad_alloc into FACET_OUT_OF_MEMORY.
template <class Fn>
inline facet_status guarded(std::string* error, Fn&& fn) noexcept {
  try {
    return fn();
  } catch (const std::bad_alloc&) {
    if (error) {
      try {
        *error = "out of memory";
      } catch (...) {
      }
    }
    return FACET_OUT_OF_MEMORY;
  } catch (...) {
    // facet throws nothing else; a host's callback (progress, resolver) may: never let it cross
    // into C, and say what happened.
    if (error) {
      try {
        try {
          throw;
        } catch (const std::exception& e) {
          *error = std::string("an exception escaped a callback of the host's: ") + facet::quote(e.what(), 200);
        } catch (...) {
          *error = "an exception that is not a std::exception escaped a callback of the host's";
        }
      } catch (...) {
      }
    }
    return FACET_INVALID_ARGUMENT;
  }
}

inline bool to_options(const facet_render_config& c, facet::RenderOptions& o, std::string& error) {
  const long shading_i = raw(c.shading), path_i = raw(c.path), isa_i = raw(c.isa), cull_i = raw(c.cull);
  if (shading_i < FACET_FLAT || shading_i > FACET_PHONG) return fail(error, "config.shading", "unknown shading"), false;
  if (path_i < FACET_PATH_REFERENCE || path_i > FACET_PATH_SIMD) return fail(error, "config.path", "unknown path"), false;
  if (isa_i < FACET_ISA_BEST || isa_i > FACET_ISA_AVX512) return fail(error, "config.isa", "unknown ISA"), false;
  if (cull_i < FACET_CULL_NONE || cull_i > FACET_CULL_FRONT) return fail(error, "config.cull", "unknown cull mode"), false;
  const facet::ShadingMode shading[] = {facet::ShadingMode::flat, facet::ShadingMode::gouraud, facet::ShadingMode::phong};
  const facet::LightingPath path[] = {facet::LightingPath::reference, facet::LightingPath::scalar,
                                      facet::LightingPath::simd};
  const facet::Isa isa[] = {facet::Isa::best, facet::Isa::sse2, facet::Isa::avx2, facet::Isa::avx512};
  const facet::CullMode cull[] = {facet::CullMode::none, facet::CullMode::back, facet::CullMode::front};
  const long pow_i = raw(c.pow_tier);
  if (pow_i < FACET_POW_AUTO || pow_i > FACET_POW_SCHLICK) return fail(error, "config.pow_tier", "unknown pow tier"), false;
  const facet::PowTier pow[] = {facet::PowTier::automatic, facet::PowTier::exact, facet::PowTier::fast,
                                facet::PowTier::integer, facet::PowTier::schlick};
  o.pow_tier = pow[pow_i];
  const long pixels_i = raw(c.pixel_precision);
  if (pixels_i < FACET_PIXELS_AUTO || pixels_i > FACET_PIXELS_FAST)
    return fail(error, "config.pixel_precision", "unknown pixel precision"), false;
  const facet::PixelPrecision pixels[] = {facet::PixelPrecision::automatic, facet::PixelPrecision::exact,
                                          facet::PixelPrecision::fast};
  o.pixel_precision = pixels[pixels_i];
  const long depth_i = raw(c.depth_mode);
  if (depth_i < FACET_DEPTH_AUTO || depth_i > FACET_DEPTH_REVERSED) return fail(error, "config.depth_mode", "unknown depth mode"), false;
  const facet::DepthMode depth[] = {facet::DepthMode::automatic, facet::DepthMode::gl, facet::DepthMode::reversed};
  o.depth = depth[depth_i];
  o.hdr = c.hdr != 0;
  o.cull_lights = c.cull_lights != 0;
  o.light_every_vertex = c.light_every_vertex != 0;
  o.vertex_relief = c.vertex_relief != 0;
  o.shading = shading[shading_i];
  o.path = path[path_i];
  o.isa = isa[isa_i];
  o.cull = cull[cull_i];
  o.tile_size = c.tile_size;
  if (c.samples != 1 && c.samples != 4 && c.samples != 8 && c.samples != 16) {
    return fail(error, "config.samples", "expected 1, 4, 8 or 16 samples per pixel"), false;
  }
  o.samples = c.samples;
  o.threads = c.threads;
  for (int i = 0; i < 4; ++i) o.clear_color[static_cast<std::size_t>(i)] = c.clear_color[i];
  o.srgb = c.srgb != 0;
  o.memory_budget_bytes = c.memory_budget_bytes;
  o.progress = nullptr;
  if (c.progress) {
    o.progress = [fn = c.progress, user = c.progress_user](double done) { return fn(user, done) != 0; };
  }
  return true;
}


inline facet::Material to_material(const facet_material& c) {
  facet::Material m;
  const facet_material* material = &c;
  m.emissive = facet::Color3(vec3(material->emissive));
    m.ambient = facet::Color3(vec3(material->ambient));
    m.diffuse = facet::Color3(vec3(material->diffuse));
    m.specular = facet::Color3(vec3(material->specular));
    m.shininess = material->shininess;
    m.alpha = material->alpha;
    m.diffuse_texture = material->diffuse_texture;
    m.texture_mode = static_cast<facet::TextureMode>(material->texture_mode);
    m.uv_scale = facet::Vec2(material->uv_scale[0], material->uv_scale[1]);
    m.alpha_cutoff = material->alpha_cutoff;
    m.blend = static_cast<facet::BlendMode>(material->blend);
    m.depth_write = static_cast<facet::DepthWrite>(material->depth_write);
    m.emissive_texture = material->emissive_texture;
    m.emission_after_texture = material->emission_after_texture != 0;
    // Enums read through their bits (any int may arrive); out of range: a value validation refuses.
    const long mode = raw(material->environment_mode), blend = raw(material->environment_blend);
    m.environment.mode = static_cast<facet::EnvironmentMode>(mode >= 0 && mode <= 3 ? mode : 255);
    m.environment.blend = static_cast<facet::EnvironmentBlend>(blend >= 0 && blend <= 2 ? blend : 255);
    for (int k = 0; k < 6; ++k) m.environment.maps[k] = material->environment_maps[k];
    m.environment.strength = material->environment_strength;
    m.environment.dynamic = material->environment_dynamic != 0;
    m.environment.resolution = material->environment_resolution;
    const long lobe = raw(material->specular_model);
    m.specular_model = static_cast<facet::SpecularModel>(lobe >= 0 && lobe <= 1 ? lobe : 255);
    m.normal_texture = material->normal_texture;
    m.normal_scale = material->normal_scale;
    m.occlusion_texture = material->occlusion_texture;
    m.occlusion_strength = material->occlusion_strength;
    m.bump_texture = material->bump_texture;
    m.bump_scale = material->bump_scale;
    m.alpha_to_coverage = material->alpha_to_coverage != 0;
  return m;
}

// The material's textures exist (checked at the call, so the error names its argument).
inline bool textures_exist(const facet::Material& m, const facet::Scene& s, const char*& field) {
  for (const auto& [index, name] : {std::pair{m.diffuse_texture, "material.diffuse_texture"},
                                    std::pair{m.emissive_texture, "material.emissive_texture"}}) {
    if (index != facet::kNoTexture && (index < 0 || static_cast<std::size_t>(index) >= s.textures.size())) {
      field = name;
      return false;
    }
  }
  for (const std::int32_t index : m.environment.maps) {
    if (index != facet::kNoTexture && (index < 0 || static_cast<std::size_t>(index) >= s.textures.size())) {
      field = "material.environment_maps";
      return false;
    }
  }
  return true;
}


inline void write_stats(const facet::FrameStats& s, facet_frame_stats* stats) {
      stats->triangles_in = s.triangles_in;
      stats->triangles_drawn = s.triangles_drawn;
      stats->vertices_lit = s.vertices_lit;
      stats->pixels_filled = s.pixels_filled;
      stats->seconds_total = s.seconds_total;
      stats->threads = s.threads;
      stats->triangles_culled = s.triangles_culled;
      stats->triangles_clipped = s.triangles_clipped;
      stats->triangles_outside = s.triangles_outside;
      stats->triangles_degenerate = s.triangles_degenerate;
      stats->triangles_small = s.triangles_small;
      stats->triangles_nonfinite = s.triangles_nonfinite;
      stats->bin_entries = s.bin_entries;
      stats->vertices_skipped = s.vertices_skipped;
      stats->vertex_lights_evaluated = s.vertex_lights_evaluated;
      stats->vertex_lights_skipped = s.vertex_lights_skipped;
      stats->pixels_tested = s.pixels_tested;
      stats->seconds_lighting = s.seconds_lighting;
      stats->seconds_geometry = s.seconds_geometry;
      stats->seconds_raster = s.seconds_raster;
      stats->seconds_resolve = s.seconds_resolve;
      stats->seconds_shadows = s.seconds_shadows;
      stats->shadow_casters = s.shadow_casters;
      stats->shadow_map_texels = s.shadow_map_texels;
      stats->shadow_map_pixels = s.shadow_map_pixels;
      if (stats->struct_size == 0 || stats->struct_size >= offsetof(facet_frame_stats, seconds_environment) + sizeof(double)) {
        stats->seconds_environment = s.seconds_environment;
      }
      if (stats->struct_size == 0 || stats->struct_size >= offsetof(facet_frame_stats, exposure_ev) + sizeof(float)) {
        stats->exposure_ev = s.exposure_ev;
      }
}

}  // namespace facet::c_api
