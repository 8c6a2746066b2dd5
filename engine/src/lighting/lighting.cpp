// Public lighting entry points: validate, set up once per call, run the chosen path.
#include "facet/lighting.hpp"

#include <new>

#include "common/look_at.hpp"
#include "lighting/point_shader.hpp"
#include "scene/validate.hpp"

namespace facet {

const char* to_string(LightingPath path) noexcept {
  switch (path) {
    case LightingPath::reference: return "reference";
    case LightingPath::scalar: return "scalar";
    case LightingPath::simd: return "simd";
  }
  return "unknown";
}

const char* to_string(Isa isa) noexcept {
  switch (isa) {
    case Isa::best: return "best";
    case Isa::sse2: return "sse2";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "unknown";
}

const char* to_string(PowTier tier) noexcept {
  switch (tier) {
    case PowTier::automatic: return "auto";
    case PowTier::exact: return "exact";
    case PowTier::fast: return "fast";
    case PowTier::integer: return "integer";
    case PowTier::schlick: return "schlick";
  }
  return "unknown";
}

// GCC's __builtin_cpu_supports checks CPUID and, for AVX and AVX-512, that the OS saves the wide
// registers (XCR0), unlike xsimd 8.1's detection (shared/design/platform.md, trap 6).
bool isa_supported(Isa isa) noexcept {
  switch (isa) {
    case Isa::best:
    case Isa::sse2: return true;  // x86-64 baseline
    case Isa::avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("fma");
  }
  return false;
}

Isa best_isa() noexcept {
  if (isa_supported(Isa::avx512)) return Isa::avx512;
  if (isa_supported(Isa::avx2)) return Isa::avx2;
  return Isa::sse2;
}

Status light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options,
                      VertexColors& out) {
  if (instance >= scene.objects.size()) {
    return {ErrorCode::invalid_argument, "instance",
            "instance: index " + std::to_string(instance) + " is out of range (" +
                std::to_string(scene.objects.size()) + " objects)"};
  }
  if (Status s = validate_lighting_inputs(scene); !s.ok()) return s;
  try {
    const Instance& inst = scene.objects[instance];
    const Eigen::Matrix4d view = look_at_d(scene.camera);
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    const lighting::EyeSphere bounds = lighting::eye_bounding_sphere(mesh, view, inst.model);
    lighting::PointShader shader;
    if (Status s = shader.prepare(scene, view, scene.materials[inst.material], options, &bounds); !s.ok()) return s;
    lighting::SoaScratch scratch;
    out.front.resize(mesh.vertex_count());
    shader.light_mesh(mesh, view, inst.model, false, 0, mesh.vertex_count(), out.front.data(), scratch);
    if (scene.two_sided) {
      out.back.resize(mesh.vertex_count());
      shader.light_mesh(mesh, view, inst.model, true, 0, mesh.vertex_count(), out.back.data(), scratch);
    } else {
      out.back.clear();
    }
  } catch (const std::bad_alloc&) {
    return {ErrorCode::invalid_argument, "instance", "out of memory for the vertex colours"};
  }
  return {};
}

}  // namespace facet
