// Public lighting entry points: validate, set up once per call, run the chosen path.
#include "facet/lighting.hpp"

#include <algorithm>
#include <new>
#include <optional>
#include <vector>

#include <tbb/info.h>

#include "common/look_at.hpp"
#include "common/parallel.hpp"
#include "lighting/image_light.hpp"
#include "lighting/point_shader.hpp"
#include "lighting/setup.hpp"
#include "scene/validate.hpp"

namespace facet {
namespace {

// Vertices per chunk of light_instance(): each is bounded, culled and lit in one pass, on any
// thread; far more work than a task costs (with a few lights), and few enough to stay in L2
// with their SoA copies.
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

// A Lighter's threads and working memory, kept between calls.
struct Lighter::Impl {
  // A thread's part: the SoA streams and its copy of the shader for the chunk at hand.
  struct Part {
    lighting::SoaScratch scratch;
    lighting::PointShader shader;
  };
  std::optional<parallel::Arena> arena;
  int arena_threads = 0;  // the count the arena was made for
  lighting::PointShader shader;
  std::vector<Part> parts;
  // PBR materials' DFG table and prepared surroundings (made for the first PBR material).
  std::unique_ptr<lighting::ImageLight> image_light;
};

Lighter::Lighter() : impl_(std::make_unique<Impl>()) {}
Lighter::~Lighter() = default;
Lighter::Lighter(Lighter&&) noexcept = default;
Lighter& Lighter::operator=(Lighter&&) noexcept = default;

Status light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options, VertexColors& out) {
  Lighter lighter;
  return lighter.light_instance(scene, instance, options, out);
}

Status Lighter::light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options,
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
  if (!impl_) impl_ = std::make_unique<Impl>();  // a moved-from Lighter works again
  Impl& im = *impl_;
  try {
    const Instance& inst = scene.objects[instance];
    const Eigen::Matrix4d view = look_at_d(scene.camera);
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    const std::size_t n = mesh.vertex_count();
    // 0: as many as the renderer takes for RenderOptions::threads = 0.
    const int threads = options.threads == 0 ? tbb::info::default_concurrency() : options.threads;
    const bool parallel = threads > 1 && n > kParallelChunk;
    if (parallel && (!im.arena || im.arena_threads != threads)) {
      im.arena.reset();
      im.arena.emplace(threads);
      im.arena_threads = threads;
    }
    lighting::PointShader& shader = im.shader;
    // A mesh with vertex colours lights them as the albedo (glColorMaterial(AMBIENT_AND_DIFFUSE)).
    lighting::LightingFeatures features;
    features.color_material = !mesh.colors.empty();
    if (scene.materials[inst.material].model == MaterialModel::pbr) {
      if (!im.image_light) im.image_light = std::make_unique<lighting::ImageLight>();
      const auto in_turn = [](std::size_t count, const std::function<void(std::size_t)>& fn) {
        for (std::size_t i = 0; i < count; ++i) fn(i);
      };
      if (Status s = im.image_light->prepare(scene.environment_light, in_turn); !s.ok()) return s;
      features.image_light = im.image_light.get();
    }
    // Prepared without bounds: every light. Each chunk then drops the lights that cannot reach its
    // own vertices (the frame plan's culling per chunk, against the sphere around the chunk's box),
    // so the positions are read chunk by chunk while they are in cache, with no pass over the
    // whole mesh before the lighting starts.
    if (Status s = shader.prepare(scene, view, scene.materials[inst.material], options, nullptr, features); !s.ok()) {
      return s;
    }
    const bool per_part = shader.culls_per_part();
    const lighting::SimdKernels* kernels = options.path == LightingPath::simd ? lighting::simd_kernels(options.isa) : nullptr;
    const lighting::simd::BoxFunction box = kernels ? kernels->box : nullptr;
    out.front.resize(n);
    const bool two_sided = scene.two_sided || inst.double_sided;
    if (two_sided) {
      out.back.resize(n);
    } else {
      out.back.clear();
    }
    // Chunks fixed by the vertex count (kParallelChunk from 0), each lit independently: the split
    // over threads cannot change a byte.
    auto light_chunk = [&](std::size_t begin, std::size_t end, Impl::Part& part) {
      const lighting::PointShader* chunk = &shader;
      if (per_part) {
        part.shader.cull_from(shader, lighting::eye_box_sphere(mesh.positions.data() + begin, end - begin, view, inst.model, box));
        chunk = &part.shader;
      }
      chunk->light_mesh(mesh, view, inst.model, false, begin, end, out.front.data(), part.scratch);
      if (two_sided) chunk->light_mesh(mesh, view, inst.model, true, begin, end, out.back.data(), part.scratch);
    };
    const std::size_t slots = parallel ? static_cast<std::size_t>(im.arena->threads()) : 1;
    if (im.parts.size() < slots) im.parts.resize(slots);
    if (!parallel) {
      for (std::size_t begin = 0; begin < n; begin += kParallelChunk) {
        light_chunk(begin, std::min(n, begin + kParallelChunk), im.parts[0]);
      }
    } else {
      im.arena->execute([&] {
        im.arena->parallel_for(tbb::blocked_range<std::size_t>(0, (n + kParallelChunk - 1) / kParallelChunk, 1),
                               [&](const tbb::blocked_range<std::size_t>& r, int slot) {
                                 for (std::size_t c = r.begin(); c < r.end(); ++c) {
                                   light_chunk(c * kParallelChunk, std::min(n, (c + 1) * kParallelChunk),
                                               im.parts[static_cast<std::size_t>(slot)]);
                                 }
                               });
      });
    }
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "instance", "out of memory for the vertex colours"};
  }
  return {};
}

}  // namespace facet
