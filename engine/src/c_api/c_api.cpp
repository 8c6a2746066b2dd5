// The C API (facet/facet.h) over the C++ library: defaults, renderers, rendering. Every entry
// point is noexcept: C++ exceptions (only std::bad_alloc can arise here) become
// FACET_OUT_OF_MEMORY, and every failure is recorded in the handle's last-error string.
#include "c_api/handles.hpp"

using namespace facet::c_api;  // NOLINT(google-build-using-namespace): the C API's shared helpers

extern "C" {

facet_render_config facet_render_config_default(void) {
  const facet::RenderOptions o;
  facet_render_config c{};
  c.shading = FACET_GOURAUD;
  c.path = FACET_PATH_SIMD;
  c.isa = FACET_ISA_BEST;
  c.cull = FACET_CULL_BACK;
  c.tile_size = o.tile_size;
  c.threads = o.threads;
  for (int i = 0; i < 4; ++i) c.clear_color[i] = o.clear_color[static_cast<std::size_t>(i)];
  c.srgb = o.srgb ? 1 : 0;
  c.memory_budget_bytes = o.memory_budget_bytes;
  c.progress = nullptr;
  c.progress_user = nullptr;
  c.pow_tier = FACET_POW_AUTO;
  c.hdr = o.hdr ? 1 : 0;
  c.cull_lights = o.cull_lights ? 1 : 0;
  c.light_every_vertex = o.light_every_vertex ? 1 : 0;
  c.depth_mode = FACET_DEPTH_AUTO;
  c.vertex_relief = o.vertex_relief ? 1 : 0;
  c.pixel_precision = FACET_PIXELS_AUTO;
  c.samples = o.samples;
  return c;
}

facet_material facet_material_default(void) {
  const facet::Material m;
  facet_material c{};
  for (int i = 0; i < 3; ++i) {
    c.emissive[i] = m.emissive[i], c.ambient[i] = m.ambient[i];
    c.diffuse[i] = m.diffuse[i], c.specular[i] = m.specular[i];
  }
  c.shininess = m.shininess;
  c.alpha = m.alpha;
  c.diffuse_texture = m.diffuse_texture;
  c.texture_mode = static_cast<facet_texture_mode>(m.texture_mode);
  c.uv_scale[0] = m.uv_scale.x(), c.uv_scale[1] = m.uv_scale.y();
  c.alpha_cutoff = m.alpha_cutoff;
  c.blend = static_cast<facet_blend>(m.blend);
  c.depth_write = static_cast<facet_depth_write>(m.depth_write);
  c.emissive_texture = m.emissive_texture;
  c.emission_after_texture = m.emission_after_texture ? 1 : 0;
  c.environment_mode = static_cast<facet_environment_mode>(m.environment.mode);
  for (int k = 0; k < 6; ++k) c.environment_maps[k] = m.environment.maps[k];
  c.environment_strength = m.environment.strength;
  c.environment_blend = static_cast<facet_environment_blend>(m.environment.blend);
  c.environment_dynamic = m.environment.dynamic ? 1 : 0;
  c.environment_resolution = m.environment.resolution;
  c.specular_model = static_cast<facet_specular_model>(m.specular_model);
  c.normal_texture = m.normal_texture;
  c.normal_scale = m.normal_scale;
  c.occlusion_texture = m.occlusion_texture;
  c.occlusion_strength = m.occlusion_strength;
  c.bump_texture = m.bump_texture;
  c.bump_scale = m.bump_scale;
  c.alpha_to_coverage = m.alpha_to_coverage ? 1 : 0;
  return c;
}

facet_fog facet_fog_default(void) {
  const facet::Fog f;
  facet_fog c{};
  c.mode = static_cast<facet_fog_mode>(f.mode);
  for (int i = 0; i < 3; ++i) c.color[i] = f.color[i];
  c.start = f.start, c.end = f.end, c.density = f.density;
  return c;
}

facet_light facet_light_default(void) {
  const facet::Light l;
  facet_light c{};
  c.type = FACET_DIRECTIONAL;
  for (int i = 0; i < 3; ++i) {
    c.position[i] = l.position[i], c.direction[i] = l.direction[i];
    c.ambient[i] = l.ambient[i], c.diffuse[i] = l.diffuse[i], c.specular[i] = l.specular[i];
  }
  c.constant_attenuation = l.constant_attenuation;
  c.linear_attenuation = l.linear_attenuation;
  c.quadratic_attenuation = l.quadratic_attenuation;
  c.spot_cutoff_deg = l.spot_cutoff_deg;
  c.spot_exponent = l.spot_exponent;
  c.shadow_method = static_cast<facet_shadow_method>(l.shadow.method);
  c.shadow_resolution = l.shadow.resolution;
  c.shadow_filter = static_cast<facet_shadow_filter>(l.shadow.filter);
  c.shadow_bias_constant = l.shadow.bias.constant;
  c.shadow_bias_slope = l.shadow.bias.slope;
  c.shadow_bias_normal = l.shadow.bias.normal;
  c.enabled = l.enabled ? 1 : 0;
  c.range = l.range;
  c.spot_smooth = l.spot_shape == facet::SpotShape::smooth_cone ? 1 : 0;
  c.spot_inner_deg = l.spot_inner_deg;
  c.spot_outer_deg = l.spot_outer_deg;
  c.spot_falloff = l.spot_falloff;
  c.attenuation_model = static_cast<facet_attenuation_model>(l.attenuation_model);
  c.range_min = l.range_min;
  c.range_max = l.range_max;
  c.projector_texture = l.projector.texture;
  c.projector_mode = static_cast<facet_projector_mode>(l.projector.mode);
  return c;
}

facet_camera facet_camera_default(void) {
  const facet::Camera k;
  facet_camera c{};
  for (int i = 0; i < 3; ++i) c.eye[i] = k.eye[i], c.target[i] = k.target[i], c.up[i] = k.up[i];
  c.vertical_fov_deg = k.vertical_fov_deg;
  c.near_plane = k.near;
  c.far_plane = k.far;
  return c;
}

facet_renderer* facet_renderer_create(const facet_render_config* config, facet_status* status) {
  facet_renderer* r = nullptr;
  std::string error;
  const facet_status s = guarded(&error, [&] {
    facet::RenderOptions o;
    if (config && !to_options(*config, o, error)) return FACET_INVALID_ARGUMENT;
    if (const facet::Status check = facet::check_render_options(o); !check.ok()) return to_c(check.code());
    r = new facet_renderer{facet::Renderer(o), {}};
    return FACET_OK;
  });
  if (status) *status = s;
  return s == FACET_OK ? r : nullptr;
}

void facet_renderer_destroy(facet_renderer* renderer) { delete renderer; }

const char* facet_renderer_last_error(const facet_renderer* renderer) {
  return renderer ? renderer->error.c_str() : "renderer: null handle";
}

const char* facet_version(void) { return facet::version(); }

size_t facet_explain_empty_frame(const facet_frame_stats* stats, char* buffer, size_t size) {
  std::string text;
  try {
    if (stats) {
      facet::FrameStats s;
      s.triangles_in = stats->triangles_in;
      s.triangles_drawn = stats->triangles_drawn;
      s.pixels_filled = stats->pixels_filled;
      s.triangles_outside = stats->triangles_outside;
      s.triangles_culled = stats->triangles_culled;
      s.triangles_small = stats->triangles_small;
      s.triangles_degenerate = stats->triangles_degenerate;
      s.triangles_nonfinite = stats->triangles_nonfinite;
      text = facet::explain_empty_frame(s);
    }
  } catch (...) {
    text.clear();
  }
  if (buffer && size > 0) {
    const std::size_t n = std::min(size - 1, text.size());
    std::memcpy(buffer, text.data(), n);
    buffer[n] = '\0';
  }
  return text.size();
}

facet_status facet_render(facet_renderer* renderer, const facet_scene* scene, void* pixels, int width, int height,
                          size_t stride_bytes, facet_pixel_format format, int y_up, float* depth,
                          size_t depth_stride_bytes, facet_frame_stats* stats) {
  if (!renderer) return FACET_INVALID_ARGUMENT;
  return guarded(&renderer->error, [&] {
    if (!scene) return fail(renderer->error, "scene", "null");
    const long format_i = raw(format);
    if (format_i < FACET_RGBA8 || format_i > FACET_RGBA32F) return fail(renderer->error, "format", "unknown pixel format");
    // facet 0.1's struct is the smallest there will be; a later library writes only the counters
    // that fit a smaller (older) struct_size.
    constexpr std::size_t kFirstStatsSize = offsetof(facet_frame_stats, exposure_ev);
    if (stats && stats->struct_size != 0 && stats->struct_size < kFirstStatsSize) {
      return fail(renderer->error, "stats.struct_size",
                  "expected sizeof(facet_frame_stats) (" + std::to_string(sizeof(facet_frame_stats)) + ") or 0, found " +
                      std::to_string(stats->struct_size));
    }
    const facet::PixelFormat formats[] = {facet::PixelFormat::rgba8, facet::PixelFormat::bgra8,
                                          facet::PixelFormat::rgba32f};
    const facet::ImageView color{pixels, width, height, stride_bytes, formats[format_i], y_up != 0};
    const facet::DepthView depth_view{depth, width, height, depth_stride_bytes, y_up != 0};
    facet::FrameStats s;
    const facet::Status status = renderer->renderer.render(scene->scene, color, depth ? &depth_view : nullptr, &s);
    if (status.ok() && stats) {
      // This version's counters; a caller's larger struct (a later header) keeps its further fields.
      const std::size_t size = stats->struct_size;
      write_stats(s, stats);
      stats->struct_size = size;
    }
    return report(renderer->error, status);
  });
}


}  // extern "C"
