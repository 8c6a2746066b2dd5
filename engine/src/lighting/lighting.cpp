// Public lighting entry points: validate, set up once per call, run the chosen path.
#include "facet/lighting.hpp"

#include <new>

#include "common/look_at.hpp"
#include "lighting/setup.hpp"
#include "scene/validate.hpp"

namespace facet {

const char* to_string(LightingPath path) noexcept {
  switch (path) {
    case LightingPath::reference: return "reference";
    case LightingPath::scalar: return "scalar";
  }
  return "unknown";
}

namespace {

template <class T>
void light_with(const Scene& scene, const Instance& inst, const LightingOptions& options, VertexColors& out) {
  const Eigen::Matrix4d view = look_at_d(scene.camera);
  const auto sp = lighting::make_shade_params<T>(scene, view, scene.materials[inst.material], options.clamp);
  const auto xf = lighting::make_eye_transform<T>(view, inst.model);
  const Mesh& mesh = scene.meshes[inst.mesh].mesh;
  out.front.resize(mesh.vertex_count());
  lighting::light_mesh<T>(sp, xf, mesh, false, out.front.data());
  if (scene.two_sided) {
    out.back.resize(mesh.vertex_count());
    lighting::light_mesh<T>(sp, xf, mesh, true, out.back.data());
  } else {
    out.back.clear();
  }
}

}  // namespace

Status light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options,
                      VertexColors& out) {
  if (instance >= scene.objects.size()) {
    return {ErrorCode::invalid_argument, "instance",
            "instance: index " + std::to_string(instance) + " is out of range (" +
                std::to_string(scene.objects.size()) + " objects)"};
  }
  if (Status s = validate_lighting_inputs(scene); !s.ok()) return s;
  try {
    switch (options.path) {
      case LightingPath::reference: light_with<double>(scene, scene.objects[instance], options, out); break;
      case LightingPath::scalar: light_with<float>(scene, scene.objects[instance], options, out); break;
      default: return {ErrorCode::invalid_argument, "path", "path: unknown lighting path"};
    }
  } catch (const std::bad_alloc&) {
    return {ErrorCode::invalid_argument, "instance", "out of memory for the vertex colours"};
  }
  return {};
}

}  // namespace facet
