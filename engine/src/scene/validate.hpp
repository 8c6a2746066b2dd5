// Internal: the part of scene validation that lighting needs (everything but per-vertex mesh data,
// whose NaN/Inf the kernels handle by definition). O(lights + materials + objects).
#pragma once

#include "facet/scene.hpp"

namespace facet {

Status validate_lighting_inputs(const Scene& scene);

}  // namespace facet
