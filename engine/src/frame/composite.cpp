// Flat and Gouraud frames with shadows, as sums of sub-frames (FrameKind).
#include <functional>

#include "io/rows.hpp"
#include "frame/frame.hpp"

namespace facet {

// Flat and Gouraud shading with shadows. Each shadowed light's diffuse and specular terms are
// drawn apart from the rest, so that every pixel can take its own visibility of that light (the
// shadow's edge runs through triangles, not along them):
//   1. visibility: a Phong sub-frame of the same view finds each pixel's visibility of three
//      shadowed lights at a time with the lights' own methods (the point and normal the pixel
//      shows; plain surfaces: no texture, vertex colour or blending; only depth-writing draws);
//   2. the base: the frame in the options' shading with the shadowed lights' diffuse and specular
//      terms left out (their ambient terms stay), into floats, with the caller's depth;
//   3. one part per shadowed light: its diffuse and specular terms alone (no emission, no
//      ambient light, black fog and background), in the same shading;
//   4. per pixel, base + sum of part x visibility, clamped unless the output is HDR floats, stored
//      as the tiles store pixels.
// Every step is linear in the lighting for the materials check_render admits (modulate textures;
// opaque, alpha or premultiplied blending), so a frame whose lights all see everything is the
// unshadowed frame up to rounding (one step). Sub-frames are deterministic, so the frame is too.
// Progress is reported by the last part alone.
void Renderer::Impl::render_composite(const Scene& scene, const RenderOptions& options, const ImageView& color,
                                      const DepthView* depth) {
  const auto frame_start = Clock::now();
  const int w = color.width, h = color.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<std::size_t> shadowed;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (scene.lights[l].enabled && scene.lights[l].shadow.method != ShadowMethod::none) shadowed.push_back(l);
  }
  auto float_view = [&](std::vector<float>& buffer) {
    buffer.resize(4 * pixels);
    return ImageView{buffer.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, false};
  };
  const std::function<bool(double)>* user_progress = progress;
  progress = nullptr;
  auto finish = [&] { progress = user_progress; };
  auto stopped = [&] { return !frame_status.ok() || cancelled.load(std::memory_order_relaxed); };
  FrameStats shadow_stats;
  RenderOptions sub = options;
  sub.srgb = false;
  sub.hdr = options.hdr && color.format == PixelFormat::rgba32f;  // as the lighting would clamp into `color`
  double seconds_shadows = 0;
  // 1. Visibility, three lights a sub-frame.
  composite_visibility.resize(shadowed.size() * pixels);
  FrameKind visibility;
  visibility.kind = FrameKind::Kind::visibility;
  RenderOptions vis = sub;
  vis.shading = ShadingMode::phong;
  vis.clear_color = {1.0f, 1.0f, 1.0f, 1.0f};
  vis.hdr = false;
  vis.samples = 1;  // visibility per pixel, at its centre (the shaded point), also when multisampling
  for (std::size_t g = 0; g < shadowed.size(); g += 3) {
    for (std::size_t c = 0; c < 3; ++c) visibility.visibility_lights[c] = g + c < shadowed.size() ? shadowed[g + c] : SIZE_MAX;
    render(scene, vis, float_view(composite_part), nullptr, visibility);
    seconds_shadows += stats.seconds_total;
    if (g == 0) shadow_stats = stats;  // the casters, maps and their texels (every sub-frame draws the same)
    if (stopped()) return finish();
    for (std::size_t c = 0; c < 3 && g + c < shadowed.size(); ++c) {
      float* out = composite_visibility.data() + (g + c) * pixels;
      for (std::size_t i = 0; i < pixels; ++i) out[i] = composite_part[4 * i + c];
    }
  }
  // 2. The base.
  FrameKind part_kind;
  part_kind.kind = FrameKind::Kind::part;
  part_kind.lighting = &composite_lights;
  composite_lights.lights = scene.lights;
  composite_lights.global_ambient = scene.global_ambient;
  composite_lights.viewer = scene.viewer;
  composite_lights.two_sided = scene.two_sided;
  composite_lights.fog = scene.fog;
  for (const std::size_t l : shadowed) {
    composite_lights.lights[l].diffuse = Color3(0.0f, 0.0f, 0.0f);
    composite_lights.lights[l].specular = Color3(0.0f, 0.0f, 0.0f);
  }
  render(scene, sub, float_view(composite_base), depth, part_kind);
  const FrameStats base = stats;
  if (stopped()) return finish();
  // 3. The parts, each added times its visibility.
  RenderOptions part = sub;
  part.clear_color = {0.0f, 0.0f, 0.0f, 0.0f};
  composite_lights.global_ambient = Color3(0.0f, 0.0f, 0.0f);
  composite_lights.fog.color = Color3(0.0f, 0.0f, 0.0f);
  part_kind.without_emission = true;
  for (std::size_t k = 0; k < shadowed.size(); ++k) {
    composite_lights.lights = scene.lights;
    for (std::size_t l = 0; l < scene.lights.size(); ++l) composite_lights.lights[l].enabled = l == shadowed[k];
    composite_lights.lights[shadowed[k]].ambient = Color3(0.0f, 0.0f, 0.0f);
    if (k + 1 == shadowed.size()) progress = user_progress;
    render(scene, part, float_view(composite_part), nullptr, part_kind);
    seconds_shadows += stats.seconds_total;
    if (stopped()) return finish();
    const float* v = composite_visibility.data() + k * pixels;
    for (std::size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) composite_base[4 * i + static_cast<std::size_t>(c)] += v[i] * composite_part[4 * i + static_cast<std::size_t>(c)];
    }
  }
  finish();
  // 4. Store.
  const bool clamp = !(options.hdr && color.format == PixelFormat::rgba32f);
  const SrgbTable* srgb_table = options.srgb && color.format != PixelFormat::rgba32f ? &srgb : nullptr;
  const std::size_t bytes = color.format == PixelFormat::rgba32f ? 16 : 4;
  for (int y = 0; y < h; ++y) {
    std::uint8_t* dst = io::row_bytes(color, y);
    for (int x = 0; x < w; ++x) {
      float* rgba = composite_base.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
      if (clamp) {
        for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] > 0.0f ? (rgba[c] < 1.0f ? rgba[c] : 1.0f) : 0.0f;
      }
      tile::store_pixel(rgba, color.format, srgb_table, dst + static_cast<std::size_t>(x) * bytes);
    }
  }
  stats = base;
  stats.seconds_shadows = seconds_shadows;  // the visibility sub-frames and the parts
  stats.shadow_casters = shadow_stats.shadow_casters;
  stats.shadow_map_texels = shadow_stats.shadow_map_texels;
  stats.shadow_map_pixels = shadow_stats.shadow_map_pixels;
  stats.seconds_total = seconds_since(frame_start);
}

}  // namespace facet
