// Internal: the shadows of one frame as the lighting sees them: which method answers each
// shadowed light's visibility queries.
#pragma once

#include <span>

#include "shadow/map.hpp"
#include "shadow/raycast.hpp"
#include "shadow/volume.hpp"

namespace facet::shadow {

struct FrameShadows {
  const RayCaster* caster = nullptr;     // the casters of the ray-cast lights, or null
  std::span<const ShadowMap* const> maps;  // per scene light: its map, or null (none, or nothing to cast)
  const ShadowVolumes* volumes = nullptr;  // the masks of the volume lights, or null
  const ShadowMap* map_of(std::size_t light) const { return light < maps.size() ? maps[light] : nullptr; }
};

}  // namespace facet::shadow
