// Internal: pieces of the model importers that tests check on their own.
#pragma once

#include "facet/material.hpp"
#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

// What ModelOptions::allow_missing lets a model skip with a warning (a material library or a
// texture that is missing, refused or unreadable): anything but running out of memory or a cancel.
inline bool skippable(const Status& s) { return s.code() != ErrorCode::out_of_memory && s.code() != ErrorCode::cancelled; }
inline constexpr const char* kStrictNote = " (strict loading: ModelOptions::allow_missing false, facet --strict)";

// facet's default material for a model's surfaces that name none (an OBJ without a usable .mtl,
// a glTF primitive without "material"): GL's grey (diffuse 0.8, specular 0, shininess 0), with the
// ambient equal to the diffuse colour as a viewer lights it (GL's 0.2 left the side the lights do
// not reach near black where three.js and Blender show it grey under the same ambient light).
inline Material model_default_material() {
  Material m;
  m.name = "default";
  m.ambient = m.diffuse;
  return m;
}

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
