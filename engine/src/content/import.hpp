// Internal: pieces of the model importers that tests check on their own.
#pragma once

#include "facet/material.hpp"
#include "facet/types.hpp"

namespace facet {

// glTF's metallic-roughness material on facet's Blinn-Phong model (docs/content.md):
// mirror = metallic (1 - roughness); diffuse = ambient = base (1 - mirror);
// specular = mix(0.04, base, metallic) (1 - roughness); shininess = 2 / a^2 - 2 with a = roughness^2,
// clamped to [1, kMaxShininess].
struct PbrMapping {
  Color3 diffuse, specular;
  float shininess = 1.0f;
};
PbrMapping map_metallic_roughness(const Color3& base, float metallic, float roughness);

}  // namespace facet
