// Vertex lighting throughput per path (reference, scalar, simd per ISA and pow tier): vertices lit
// per second and vertex-lights per second, for 1, 4 and 8 lights of mixed types, on a mesh that
// fits in L1/L2 (4,096 vertices) and one that does not (1M vertices, 24 MB of positions and
// normals in, 12 MB of colours out). One thread. ISAs the CPU lacks are reported as skipped.
//
//   build/bin/facet_bench_lighting                        # everything
//   build/bin/facet_bench_lighting --benchmark_filter=scalar/4
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "facet/facet.hpp"

namespace {

// `vertex_count` vertices on a sphere in front of the camera, lit by `light_count` lights that
// cycle through point (with attenuation), GL spot, directional and smooth spot.
facet::Scene bench_scene(int vertex_count, int light_count, bool points_only = false) {
  using facet::Vec3;
  facet::Scene s;
  const int rings = std::max(2, static_cast<int>(std::sqrt(vertex_count / 2.0)));
  const int segments = std::max(3, vertex_count / (rings + 1) - 1);
  s.meshes.push_back({"sphere", facet::make_uv_sphere(1.0f, segments, rings)});
  facet::Material m;
  m.diffuse = {0.7f, 0.5f, 0.3f};
  m.specular = {0.8f, 0.8f, 0.8f};
  m.shininess = 48.0f;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, facet::Mat4::Identity()});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  for (int i = 0; i < light_count; ++i) {
    facet::Light l;
    l.position = Vec3(u(rng), u(rng), 3.0f + u(rng));
    l.direction = -l.position;
    switch (points_only ? 0 : i % 4) {
      case 0: l.type = facet::LightType::point; l.linear_attenuation = 0.1f; l.quadratic_attenuation = 0.02f; break;
      case 1: l.type = facet::LightType::spot; l.spot_cutoff_deg = 40; l.spot_exponent = 6; break;
      case 2: l.type = facet::LightType::directional; break;
      default:
        l.type = facet::LightType::spot;
        l.spot_shape = facet::SpotShape::smooth_cone;
        l.spot_inner_deg = 15;
        l.spot_outer_deg = 35;
        break;
    }
    s.lights.push_back(l);
  }
  s.camera.eye = Vec3(0, 0, 4);
  return s;
}

void BM_Lighting(benchmark::State& state, facet::LightingPath path, facet::Isa isa = facet::Isa::best,
                 facet::PowTier tier = facet::PowTier::automatic, bool points_only = false) {
  if (path == facet::LightingPath::simd && !facet::isa_supported(isa)) {
    state.SkipWithError((std::string("this CPU has no ") + facet::to_string(isa)).c_str());
    return;
  }
  const int lights = static_cast<int>(state.range(0));
  const facet::Scene scene = bench_scene(static_cast<int>(state.range(1)), lights, points_only);
  const auto vertices = static_cast<std::int64_t>(scene.meshes[0].mesh.vertex_count());
  facet::LightingOptions options;
  options.path = path;
  options.isa = isa;
  options.pow_tier = tier;
  facet::VertexColors out;
  for (auto _ : state) {
    const facet::Status s = facet::light_instance(scene, 0, options, out);
    if (!s.ok()) {
      state.SkipWithError(s.message().c_str());
      break;
    }
    benchmark::DoNotOptimize(out.front.data());
    benchmark::ClobberMemory();
  }
  using benchmark::Counter;
  state.counters["vertices_lit/s"] = Counter(static_cast<double>(vertices), Counter::kIsIterationInvariantRate);
  state.counters["vertex_lights/s"] =
      Counter(static_cast<double>(vertices * lights), Counter::kIsIterationInvariantRate);
  std::string label = facet::to_string(path);
  if (path == facet::LightingPath::simd) label += std::string(" ") + facet::to_string(isa) + " pow " + facet::to_string(tier);
  state.SetLabel(label + ", " + std::to_string(vertices) + " vertices");
}

void lighting_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"lights", "vertices"});
  for (int vertices : {4096, 1 << 20})
    for (int lights : {1, 4, 8}) b->Args({lights, vertices});
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_Lighting, reference, facet::LightingPath::reference)->Apply(lighting_args);
BENCHMARK_CAPTURE(BM_Lighting, scalar, facet::LightingPath::scalar)->Apply(lighting_args);
BENCHMARK_CAPTURE(BM_Lighting, simd_sse2, facet::LightingPath::simd, facet::Isa::sse2)->Apply(lighting_args);
BENCHMARK_CAPTURE(BM_Lighting, simd_avx2, facet::LightingPath::simd, facet::Isa::avx2)->Apply(lighting_args);
BENCHMARK_CAPTURE(BM_Lighting, simd_avx512, facet::LightingPath::simd, facet::Isa::avx512)->Apply(lighting_args);
// The pow tiers on the best ISA (the material's shininess 48 is whole: auto picks integer).
BENCHMARK_CAPTURE(BM_Lighting, simd_best_exact, facet::LightingPath::simd, facet::Isa::best, facet::PowTier::exact)
    ->Apply(lighting_args);
BENCHMARK_CAPTURE(BM_Lighting, simd_best_fast, facet::LightingPath::simd, facet::Isa::best, facet::PowTier::fast)
    ->Apply(lighting_args);
// The configuration of shared/design/targets.md: point lights with attenuation only.
void point_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"point_lights", "vertices"})->Args({4, 1 << 16})->Args({4, 1 << 20})->Unit(benchmark::kMillisecond);
}
BENCHMARK_CAPTURE(BM_Lighting, points_scalar, facet::LightingPath::scalar, facet::Isa::best, facet::PowTier::automatic,
                  true)->Apply(point_args);
BENCHMARK_CAPTURE(BM_Lighting, points_simd_best, facet::LightingPath::simd, facet::Isa::best,
                  facet::PowTier::automatic, true)->Apply(point_args);

}  // namespace

BENCHMARK_MAIN();
