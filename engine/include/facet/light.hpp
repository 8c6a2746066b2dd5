// Lights of the classic lighting model, in world space. See README "Lighting model" for the
// equation; the defaults are GL's light 0 (white diffuse and specular, no attenuation).
#pragma once

#include <cstdint>
#include <string>

#include "facet/light_kinds.hpp"
#include "facet/types.hpp"

namespace facet {

// Shadows of one light (docs/shadows.md). `raycast` is exact: a shadow ray per shaded point
// through Intel Embree; `map` draws a shadow map (spot: one perspective face; directional: one
// orthographic face fitted to the casters; point: a cube of six faces) and looks each point up in
// it, filtered; `volume` counts the casters' stencil shadow volumes per pixel (z-fail), exact and
// hard, with no filter or bias (after a depth-only pass of the camera's view).
enum class ShadowMethod { none, map, volume, raycast };
// A map's filter: the nearest texel, or N x N texels (bilinear-weighted comparisons).
enum class ShadowFilter { none, pcf2x2, pcf3x3, pcf5x5 };
const char* to_string(ShadowMethod method) noexcept;
const char* to_string(ShadowFilter filter) noexcept;

// Enabled lights with shadows per scene at most.
inline constexpr int kMaxShadowedLights = 8;

// How far a shaded point moves before its visibility is decided, in the method's unit. `map`: the
// filter's radius at the point (half the filter's width plus half a texel, in texels of the map
// there: 1 texel for none, 1.5 for pcf2x2, 2 for pcf3x3, 3 for pcf5x5), so a bias that clears
// one filter clears all; `raycast`: 1e-4 of the radius of the sphere around the shadow casters;
// `volume` uses none.
// A plane moved 1 unit along its normal clears its own map at any angle to the light; the
// default 1.5 leaves room for rounding. Each in [0, 1e4].
struct ShadowBias {
  float constant = 0.0f;  // map: towards the light
  float slope = 0.0f;     // map: towards the light, times the tangent of the angle between normal and light (capped at 10)
  float normal = 1.5f;    // map and raycast: along the point's normal
};

// A spot light that projects a picture (a slide projector, or a gobo cut-out), as GL's eye-linear
// texgen with the light's matrix does: a point's texture coordinates are its direction from the
// light in the light's view (looking along `direction`, world +y up, +x when the light points
// within 8 degrees of the vertical: the spot shadow map's view), s = 1/2 + x / (2 |z| tan(cone)),
// t = 1/2 + y / (2 |z| tan(cone)), cone the spot's cutoff (GL cone) or outer angle (smooth
// cone), so the picture's square spans the cone's width. The picture, read bilinear from level 0
// (its wrap mode ignored: outside [0, 1] and behind the light it throws no light), multiplies the
// light's diffuse and specular terms (never its ambient) at each point, per colour channel
// (`modulate`) or by its luminance 0.2126 R + 0.7152 G + 0.0722 B (`gobo`: the light keeps its
// colour). Lit per pixel only (Phong); flat and Gouraud shading light the spot without it.
enum class ProjectorMode { modulate, gobo };
inline constexpr int kMaxProjectors = 4;  // enabled spot lights with a projector per scene
struct Projector {
  std::int32_t texture = -1;  // index into Scene::textures; -1: none
  ProjectorMode mode = ProjectorMode::modulate;
};

struct Shadow {
  ShadowMethod method = ShadowMethod::none;  // none: the light casts no shadows
  int resolution = 2048;                     // map: texels a side (each face), [16, 16384]
  ShadowFilter filter = ShadowFilter::pcf3x3;  // map
  ShadowBias bias;
};

struct Light {
  std::string name;
  LightType type = LightType::directional;
  bool enabled = true;

  Vec3 position{0.0f, 0.0f, 0.0f};    // point and spot lights, world space
  Vec3 direction{0.0f, 0.0f, -1.0f};  // directional and spot lights: the way the light travels

  Color3 ambient{0.0f, 0.0f, 0.0f};
  Color3 diffuse{1.0f, 1.0f, 1.0f};
  Color3 specular{1.0f, 1.0f, 1.0f};

  // Point and spot: how the light fades with distance. gl: att = 1 / (constant + linear d +
  // quadratic d^2), all >= 0, not all zero. linear_range: att = clamp((range_max - d + range_min) /
  // range_max, 0, 1) with 0 <= range_min <= range_max, range_max > 0 (the coefficients are unused).
  AttenuationModel attenuation_model = AttenuationModel::gl;
  float range_min = 0.0f;
  float range_max = 0.0f;
  float constant_attenuation = 1.0f;
  float linear_attenuation = 0.0f;
  float quadratic_attenuation = 0.0f;
  // Point and spot: when > 0, att is also multiplied by saturate(1 - (d/range)^4)^2, so the light
  // provably contributes nothing beyond `range` (UE4 / Frostbite window). 0 = unbounded.
  float range = 0.0f;

  // Spot lights only.
  SpotShape spot_shape = SpotShape::cutoff_exponent;
  float spot_cutoff_deg = 45.0f;  // cutoff_exponent: half-angle of the cone, [0, 90] or 180
  float spot_exponent = 0.0f;     // cutoff_exponent: [0, kMaxShininess]
  float spot_inner_deg = 30.0f;   // smooth_cone: 0 <= inner <= outer <= 90
  float spot_outer_deg = 45.0f;
  float spot_falloff = 2.0f;      // smooth_cone: exponent of the ramp, [0, kMaxShininess]

  Shadow shadow;  // what blocks this light's diffuse and specular terms (its ambient term is never blocked)
  Projector projector;  // spot lights only
};

// How many faces a light's shadow map has: 6 (a cube) for point lights and for spot lights whose
// cone is wider than 75 degrees (half-angle), else 1.
int shadow_map_faces(const Light& light) noexcept;
// A shadow map filter's width in texels: 1 (none, the nearest texel), 2, 3 or 5.
int shadow_filter_width(ShadowFilter filter) noexcept;

}  // namespace facet
