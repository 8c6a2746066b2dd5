// Surface material of the classic (OpenGL 2.1 fixed-function) lighting model. Defaults are GL's.
#pragma once

#include <string>

#include "facet/types.hpp"

namespace facet {

// Largest accepted shininess and spot exponent. GL caps both at 128; facet allows more so that
// tight highlights can be studied (the pow tiers are specified up to this bound).
inline constexpr float kMaxShininess = 4096.0f;

struct Material {
  std::string name;
  Color3 emissive{0.0f, 0.0f, 0.0f};
  Color3 ambient{0.2f, 0.2f, 0.2f};
  Color3 diffuse{0.8f, 0.8f, 0.8f};
  Color3 specular{0.0f, 0.0f, 0.0f};
  float shininess = 0.0f;  // Blinn-Phong exponent in [0, kMaxShininess]; 0^0 = 1 as in GL
  float alpha = 1.0f;      // [0, 1], carried to the output's alpha channel
};

}  // namespace facet
