// Public lighting entry points: validate, set up once per call, run the chosen path.
#include "facet/lighting.hpp"

#include <new>
#include <optional>
#include <vector>

#include <tbb/info.h>

#include "common/look_at.hpp"
#include "common/parallel.hpp"
#include "lighting/point_shader.hpp"
#include "lighting/setup.hpp"
#include "scene/validate.hpp"

namespace facet {
namespace {

// Vertices per task when light_instance() runs on several threads: far more work than a task
// costs (with a few lights), and few enough to stay in L2 with their SoA copies.
constexpr std::size_t kParallelChunk = 8192;

}  // namespace

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
// registers (XCR0), unlike xsimd 8.1's detection, which reads the CPUID bits only.
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
  if (options.threads < 0 || options.threads > 1024) {
    return {ErrorCode::invalid_argument, "threads",
            "threads: " + std::to_string(options.threads) + " is outside [0, 1024] (0 = one per hardware thread)"};
  }
  if (Status s = validate_lighting_inputs(scene); !s.ok()) return s;
  try {
    const Instance& inst = scene.objects[instance];
    const Eigen::Matrix4d view = look_at_d(scene.camera);
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    const std::size_t n = mesh.vertex_count();
    // 0: as many as the renderer takes for RenderOptions::threads = 0.
    const int threads = options.threads == 0 ? tbb::info::default_concurrency() : options.threads;
    const bool parallel = threads > 1 && n > kParallelChunk;
    std::optional<parallel::Arena> arena;
    if (parallel) arena.emplace(threads);
    // The bounds' passes over the positions on the same threads (their chunks fixed by the count).
    const lighting::EyeSphere bounds = lighting::eye_bounding_sphere(mesh, view, inst.model, [&](std::size_t chunks, const auto& fn) {
      if (!parallel) return lighting::chunks_in_turn(chunks, fn);
      arena->execute([&] {
        arena->parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r, int) {
          for (std::size_t c = r.begin(); c < r.end(); ++c) fn(c);
        });
      });
    });
    lighting::PointShader shader;
    // A mesh with vertex colours lights them as the albedo (glColorMaterial(AMBIENT_AND_DIFFUSE)).
    lighting::LightingFeatures features;
    features.color_material = !mesh.colors.empty();
    if (Status s = shader.prepare(scene, view, scene.materials[inst.material], options, &bounds, features); !s.ok()) {
      return s;
    }
    out.front.resize(n);
    const bool two_sided = scene.two_sided || inst.double_sided;
    if (two_sided) {
      out.back.resize(n);
    } else {
      out.back.clear();
    }
    auto light_range = [&](std::size_t begin, std::size_t end, lighting::SoaScratch& scratch) {
      shader.light_mesh(mesh, view, inst.model, false, begin, end, out.front.data(), scratch);
      if (two_sided) shader.light_mesh(mesh, view, inst.model, true, begin, end, out.back.data(), scratch);
    };
    if (!parallel) {
      lighting::SoaScratch scratch;
      light_range(0, n, scratch);
    } else {
      // Fixed chunks, each lit independently: the split cannot change a byte.
      std::vector<lighting::SoaScratch> scratch(static_cast<std::size_t>(arena->threads()));
      arena->execute([&] {
        arena->parallel_for(tbb::blocked_range<std::size_t>(0, n, kParallelChunk),
                           [&](const tbb::blocked_range<std::size_t>& r, int slot) {
                             light_range(r.begin(), r.end(), scratch[static_cast<std::size_t>(slot)]);
                           });
      });
    }
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "instance", "out of memory for the vertex colours"};
  }
  return {};
}

}  // namespace facet
