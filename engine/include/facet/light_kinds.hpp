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

}  // namespace facet
