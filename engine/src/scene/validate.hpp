// Internal: the part of scene validation that lighting needs (everything but per-vertex mesh data,
// whose NaN/Inf the kernels handle by definition). O(lights + materials + objects).
#pragma once

#include <string>

#include "facet/scene.hpp"

namespace facet {

Status validate_lighting_inputs(const Scene& scene);

// A field path such as "lights[2].position", built only when there is an error to report:
// validating a valid scene allocates nothing (the renderer validates every frame).
struct FieldPath {
  const char* list;   // "lights", or an object such as "camera"
  std::size_t index;  // used when `indexed`
  bool indexed;
  std::string operator()(const char* member) const {
    std::string s = list;
    if (indexed) s += "[" + std::to_string(index) + "]";
    if (*member) s += std::string(".") + member;
    return s;
  }
};

// Each field of the material or light against its entry in the field table (facet/fields.hpp):
// range, type, choices. The rules between fields are validate_material's and validate_light's.
Status check_material_fields(const Material& material, const FieldPath& path);
Status check_light_fields(const Light& light, const FieldPath& path);

// validate_mesh(mesh).ok() without building any message: the allocation-free fast path.
bool mesh_is_valid(const Mesh& mesh) noexcept;

}  // namespace facet
