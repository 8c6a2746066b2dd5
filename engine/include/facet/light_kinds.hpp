// The kinds of light and of spot cone (facet/light.hpp's Light uses them). A header of its own,
// with no dependencies, so that plain-data code can name them.
#pragma once

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

// How a point or spot light fades with the distance d from it.
enum class AttenuationModel {
  // OpenGL: 1 / (k0 + k1 d + k2 d^2) (Light::constant/linear/quadratic_attenuation).
  gl,
  // The linear min/max range of the classic software-rendering tutorials: clamp((max - d + min) /
  // max, 0, 1) (Light::range_min, range_max): 1 up to d = min, falling linearly to 0 at
  // d = max + min, nothing beyond.
  linear_range,
};

}  // namespace facet
