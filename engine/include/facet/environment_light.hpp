// Light from the surroundings for PBR materials (Material::model == pbr; docs/pbr.md): a
// picture of the radiance arriving from every direction, which lights every PBR surface by
// image-based lighting (its diffuse part by order-2 spherical harmonics, its specular part by a
// prefiltered cube map and the split-sum approximation). GL materials never see it; with it, PBR
// materials do not see the scene's global ambient (which stands for the surroundings without one).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "facet/assets.hpp"
#include "facet/mesh.hpp"
#include "facet/status.hpp"

namespace facet {

enum class EnvironmentSource : std::uint8_t {
  none,    // no picture: PBR surfaces see the scene's global ambient (and the lights' ambient) all around
  studio,  // facet's neutral studio (docs/pbr.md): soft panels in a dim grey room, made in code
  image,   // EnvironmentLight::rgb
};
const char* to_string(EnvironmentSource source) noexcept;

// What is drawn where no surface is (Scene::background).
enum class Background : std::uint8_t {
  colour,       // the render's clear colour (RenderOptions::clear_color), as stored
  environment,  // the surroundings (Scene::environment_light: the studio or the picture, times its
                // intensity, turned as it is), opaque, exposed and tone-mapped as the surfaces are
};
const char* to_string(Background background) noexcept;

// Largest side of an environment picture (a texel count the prefilter's first pass reads whole).
inline constexpr int kMaxEnvironmentSide = 16384;

struct EnvironmentLight {
  EnvironmentSource source = EnvironmentSource::none;
  // image: an equirectangular picture of linear RGB radiance, 3 floats a texel, top row first,
  // width = 2 height, read as three.js (and <model-viewer>) read one: direction d is seen at
  // u = 1/2 + atan2(d.z, d.x) / 2 pi, v = 1/2 + asin(d.y) / pi (v = 1 the top row): the picture's
  // centre column is seen along +X, its left edge along -X, a quarter of the way along -Z.
  // Every value finite and >= 0.
  int width = 0, height = 0;
  std::vector<float> rgb;
  float intensity = 1.0f;     // multiplies the radiance; [0, 1e6]
  float rotation_deg = 0.0f;  // turns the surroundings about world +Y (counter-clockwise seen from above); [-3600, 3600]
};

// An environment picture from a file's bytes: Radiance .hdr (RGBE, flat or run-length encoded; its
// EXPOSURE divided out; RGBE decoded as Radiance does, (m + 1/2) 2^(e - 136)), OpenEXR (RGB, alpha
// ignored; negative, infinite or NaN texels refused) or 8-bit PNG or JPEG (sRGB, decoded to linear),
// told apart by their signatures; equirectangular (twice as wide as high). The memory budget (0:
// none) bounds the picture's floats, checked before they are allocated. `source_name` is used in
// messages. Returns source image, intensity 1, rotation 0.
Result<EnvironmentLight> decode_environment_image(std::span<const std::uint8_t> bytes, const std::string& source_name,
                                                  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes);
// The same from a file the host names (regular files only; through AssetAccess::resolver when set).
Result<EnvironmentLight> load_environment_image(const std::string& path, const AssetAccess& access = {},
                                                std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes);

}  // namespace facet
