// Internal: the part of scene validation that lighting needs (everything but per-vertex mesh data,
// whose NaN/Inf the kernels handle by definition). O(lights + materials + objects).
#pragma once

#include "facet/scene.hpp"

namespace facet {

Status validate_lighting_inputs(const Scene& scene);

// validate_mesh(mesh).ok() without building any message: the allocation-free fast path.
bool mesh_is_valid(const Mesh& mesh) noexcept;

}  // namespace facet
