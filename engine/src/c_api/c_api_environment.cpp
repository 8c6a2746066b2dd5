// The C API's surroundings for PBR materials (facet.h: facet_scene_set_environment and the rest;
// Scene::environment_light) and the background (Scene::background).
#include <cstring>

#include "c_api/handles.hpp"

using namespace facet::c_api;  // NOLINT(google-build-using-namespace): the C API's shared helpers

namespace {

facet_status set(facet_scene* scene, facet::EnvironmentLight e, float intensity, float rotation_deg) {
  e.intensity = intensity;
  e.rotation_deg = rotation_deg;
  if (facet::Status st = facet::validate_environment_light(e); !st.ok()) return report(scene->error, st);
  scene->scene.environment_light = std::move(e);
  return report(scene->error, {});
}

}  // namespace

extern "C" {

facet_status facet_scene_set_environment(facet_scene* scene, facet_surroundings source, float intensity,
                                         float rotation_deg) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const long s = raw(source);
    if (s != FACET_SURROUNDINGS_NONE && s != FACET_SURROUNDINGS_STUDIO) {
      return fail(scene->error, "source", "FACET_SURROUNDINGS_NONE or FACET_SURROUNDINGS_STUDIO (a picture: facet_scene_load_environment_image or facet_scene_set_environment_pixels)");
    }
    facet::EnvironmentLight e;
    e.source = s == FACET_SURROUNDINGS_STUDIO ? facet::EnvironmentSource::studio : facet::EnvironmentSource::none;
    return set(scene, std::move(e), intensity, rotation_deg);
  });
}

facet_status facet_scene_load_environment_image(facet_scene* scene, const char* path, float intensity, float rotation_deg,
                                                uint64_t memory_budget_bytes) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!path) return fail(scene->error, "path", "null");
    facet::Result<facet::EnvironmentLight> e = facet::load_environment_image(path, scene->assets, memory_budget_bytes);
    if (!e) return report(scene->error, e.status());
    return set(scene, std::move(*e), intensity, rotation_deg);
  });
}

facet_status facet_scene_set_environment_pixels(facet_scene* scene, const float* rgb, int width, int height, float intensity,
                                                float rotation_deg) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!rgb) return fail(scene->error, "rgb", "null");
    if (width < 2 || height < 1 || width > facet::kMaxEnvironmentSide || height > facet::kMaxEnvironmentSide || width != 2 * height) {
      return fail(scene->error, "width", "an equirectangular picture is twice as wide as high, at most 16384 texels a side");
    }
    facet::EnvironmentLight e;
    e.source = facet::EnvironmentSource::image;
    e.width = width, e.height = height;
    const std::size_t n = std::size_t(width) * std::size_t(height) * 3;
    e.rgb.assign(rgb, rgb + n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!(e.rgb[i] >= 0.0f && e.rgb[i] <= 3.4e38f)) {
        return fail(scene->error, "rgb", "texel " + std::to_string(i / 3) + " holds a negative, infinite or NaN value");
      }
    }
    return set(scene, std::move(e), intensity, rotation_deg);
  });
}

facet_status facet_scene_get_environment(const facet_scene* scene, facet_surroundings* source, int* width, int* height,
                                         float* intensity, float* rotation_deg) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  const facet::EnvironmentLight& e = scene->scene.environment_light;
  if (source) *source = static_cast<facet_surroundings>(e.source);
  if (width) *width = e.width;
  if (height) *height = e.height;
  if (intensity) *intensity = e.intensity;
  if (rotation_deg) *rotation_deg = e.rotation_deg;
  return FACET_OK;
}

facet_status facet_scene_set_background(facet_scene* scene, facet_background background) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const long b = raw(background);
    if (b != FACET_BACKGROUND_COLOUR && b != FACET_BACKGROUND_ENVIRONMENT) {
      return fail(scene->error, "background", "FACET_BACKGROUND_COLOUR or FACET_BACKGROUND_ENVIRONMENT");
    }
    scene->scene.background = b == FACET_BACKGROUND_ENVIRONMENT ? facet::Background::environment : facet::Background::colour;
    return report(scene->error, {});
  });
}

facet_status facet_scene_get_background(const facet_scene* scene, facet_background* background) {
  if (!scene || !background) return FACET_INVALID_ARGUMENT;
  *background = scene->scene.background == facet::Background::environment ? FACET_BACKGROUND_ENVIRONMENT : FACET_BACKGROUND_COLOUR;
  return FACET_OK;
}

}  // extern "C"
