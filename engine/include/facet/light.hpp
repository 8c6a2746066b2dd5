// Lights of the classic lighting model, in world space. See README "Lighting model" for the
// equation; the defaults are GL's light 0 (white diffuse and specular, no attenuation).
#pragma once

#include <string>

#include "facet/types.hpp"

namespace facet {

enum class LightType { directional, point, spot };

// How a spot light fades towards the edge of its cone.
enum class SpotShape {
  // OpenGL: (cos angle)^exponent inside `cutoff_deg`, zero outside; cutoff 180 = no cone.
  cutoff_exponent,
  // D3D9 / glTF KHR_lights_punctual: 1 inside `inner_deg`, 0 outside `outer_deg`, and between them
  // t^falloff with t the linear ramp in cos(angle) (falloff 2 is glTF's curve).
  smooth_cone,
};

// Shadows of one light (docs/shadows.md). `raycast` is exact: a shadow ray per shaded point
// through Intel Embree; `map` and `volume` are not implemented yet and are refused by validation.
enum class ShadowMethod { none, map, volume, raycast };
enum class ShadowFilter { none, pcf2x2, pcf3x3, pcf5x5 };
const char* to_string(ShadowMethod method) noexcept;
const char* to_string(ShadowFilter filter) noexcept;

// Enabled lights with shadows per scene at most.
inline constexpr int kMaxShadowedLights = 8;

struct ShadowBias {
  float constant = 0.0f;  // map: depth offset in [0, 1] window depth units
  float slope = 0.0f;     // map: times the depth slope
  // The shaded point moves this far along its normal before its visibility is decided, as a
  // fraction of the radius of the sphere bounding the shadow casters (every method).
  float normal = 1e-4f;
};

struct Shadow {
  ShadowMethod method = ShadowMethod::none;  // none: the light casts no shadows
  int resolution = 2048;                     // map: texels a side, [16, 16384]
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

  // Point and spot: att = 1 / (constant + linear d + quadratic d^2); all >= 0, not all zero.
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
};

}  // namespace facet
