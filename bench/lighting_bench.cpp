// Vertex lighting throughput per path (reference, scalar, simd per ISA and pow tier): vertices lit
// per second and vertex-lights per second. One thread unless the name ends in threads:N. Families:
//   BM_Lighting/<method>/mixed/lights:4/vertices:{4096,1048576}: every path x ISA x pow tier on
//     4 lights of mixed types (point with attenuation, GL spot, directional, smooth spot), on a
//     mesh that fits in L1/L2 and one that does not (1M vertices: 24 MB in, 12 MB out);
//   BM_Lighting/<method>/<mix>/lights:{1,4,8,16}/vertices:65536: scalar and the best ISA (pow
//     auto) as the light count grows, for mixed lights and for each type alone;
//   BM_LightingLobe/<method>/{blinn,phong}/mixed/lights:4/vertices:4096: every method with Blinn's
//     n.h and Phong's R.V specular lobe (Material::specular_model);
//   BM_Lighting/<method>/point/lights:{1,4}/vertices:{65536,1048576}/threads:{1,2}: scalar and
//     the best ISA (pow auto) on one and two threads (LightingOptions::threads; wall time), for
//     the targets "4 point lights, best ISA, 2 threads" and "1 light, data larger than cache";
//   BM_LightingPerCall/<best ISA>/point/lights:4/vertices:65536/threads:{1,2}: the same through
//     light_instance(), which makes its threads and working memory per call (every other family
//     calls one facet::Lighter, which keeps them).
// Counters: vertices_lit/s, vertex_lights/s, and the share of the machine's limits measured at
// start (bench/roofline.hpp, one thread; times the thread count for threads:N): bw_share = bytes
// the kernel must stream (24 in + 12 out per vertex) / triad bandwidth; for point lights,
// flop_share = counted flops / peak FMA rate.
// ISAs the CPU lacks are not registered.
//
//   build/bin/facet_bench_lighting                        # everything
//   build/bin/facet_bench_lighting --benchmark_filter=scalar/mixed/lights:4
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <random>
#include <string>

#include "facet/facet.hpp"
#include "roofline.hpp"

namespace {

// `vertex_count` vertices on a sphere in front of the camera, lit by `light_count` lights that
// cycle through point (with attenuation), GL spot, directional and smooth spot.
enum class Mix { mixed, directional, point, spot };
const char* to_string(Mix m) {
  switch (m) {
    case Mix::mixed: return "mixed";
    case Mix::directional: return "directional";
    case Mix::point: return "point";
    case Mix::spot: return "spot";
  }
  return "?";
}

// `pbr`: the material is glTF's (docs/pbr.md) instead of GL's; `studio`: and lit by the neutral
// studio besides the lights.
facet::Scene bench_scene(int vertex_count, int light_count, Mix mix, bool phong_lobe = false, bool pbr = false,
                         bool studio = false) {
  using facet::Vec3;
  facet::Scene s;
  const int rings = std::max(2, static_cast<int>(std::sqrt(vertex_count / 2.0)));
  const int segments = std::max(3, vertex_count / (rings + 1) - 1);
  s.meshes.push_back({"sphere", facet::make_uv_sphere(1.0f, segments, rings)});
  facet::Material m;
  m.diffuse = {0.7f, 0.5f, 0.3f};
  m.specular = {0.8f, 0.8f, 0.8f};
  m.shininess = 48.0f;
  if (phong_lobe) m.specular_model = facet::SpecularModel::phong;
  if (pbr) {
    m.model = facet::MaterialModel::pbr;
    m.base_color = {0.7f, 0.5f, 0.3f};
    m.metallic = 0.3f;
    m.roughness = 0.4f;
  }
  if (studio) s.environment_light.source = facet::EnvironmentSource::studio;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, facet::Mat4::Identity()});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  for (int i = 0; i < light_count; ++i) {
    facet::Light l;
    l.position = Vec3(u(rng), u(rng), 3.0f + u(rng));
    l.direction = -l.position;
    const int kind = mix == Mix::mixed ? i % 4 : (mix == Mix::point ? 0 : (mix == Mix::spot ? 1 : 2));
    switch (kind) {
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

// Flops per vertex and point light on the auto tier (shininess 48: integer pow), counted from
// shade_simd.hpp with sqrt and division as one each (they cost 4-8 FMAs of throughput, so the
// share below understates how busy the divider is): difference 3, |d|^2 5, sqrt 1, 1/d 1,
// direction 3, attenuation 4 + 1, n.l 5, diffuse 6, half vector 3 + normalise 10, n.h 5, pow 7,
// specular 6, accumulate 6.
constexpr double kFlopsPerPointLight = 66;

struct Method {
  std::string name;
  facet::LightingOptions options;
};

void run_lighting(benchmark::State& state, const facet::LightingOptions& options, Mix mix, int lights, int vertex_count,
                  bool phong_lobe = false, bool per_call = false, bool pbr = false, bool studio = false) {
  const facet::Scene scene = bench_scene(vertex_count, lights, mix, phong_lobe, pbr, studio);
  const auto vertices = static_cast<std::int64_t>(scene.meshes[0].mesh.vertex_count());
  facet::VertexColors out;
  facet::Lighter lighter;  // its threads and working memory kept between calls, as a caller would
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const facet::Status s = per_call ? facet::light_instance(scene, 0, options, out)
                                     : lighter.light_instance(scene, 0, options, out);
    if (!s.ok()) {
      state.SkipWithError(s.message().c_str());
      break;
    }
    benchmark::DoNotOptimize(out.front.data());
    benchmark::ClobberMemory();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double iterations = static_cast<double>(state.iterations());
  using benchmark::Counter;
  const facet::bench::Roofline& roof = facet::bench::roofline();
  state.counters["vertices_lit/s"] = Counter(static_cast<double>(vertices), Counter::kIsIterationInvariantRate);
  state.counters["vertex_lights/s"] = Counter(static_cast<double>(vertices * lights), Counter::kIsIterationInvariantRate);
  // Shares of the machine's limits (plain ratios, from the measured loop time), against the
  // one-thread figures times the threads the call used (as the frame benchmarks do).
  const double vertex_rate = iterations * static_cast<double>(vertices) / seconds;
  const double threads = options.threads > 1 ? static_cast<double>(options.threads) : 1.0;
  state.counters["bw_share"] = vertex_rate * 36.0 / (roof.triad_bytes_per_s * threads);
  if (mix == Mix::point) {
    state.counters["flop_share"] = vertex_rate * lights * kFlopsPerPointLight / (roof.peak_flops * threads);
  }
  state.SetLabel(std::to_string(vertices) + " vertices");
}

void register_all() {
  std::vector<Method> all, sweep;
  facet::LightingOptions o;
  o.path = facet::LightingPath::reference;
  all.push_back({"reference", o});
  o.path = facet::LightingPath::scalar;
  all.push_back({"scalar", o});
  sweep.push_back({"scalar", o});
  for (facet::Isa isa : {facet::Isa::sse2, facet::Isa::avx2, facet::Isa::avx512}) {
    if (!facet::isa_supported(isa)) continue;
    for (facet::PowTier tier : {facet::PowTier::automatic, facet::PowTier::exact, facet::PowTier::fast,
                                facet::PowTier::integer, facet::PowTier::schlick}) {
      o.path = facet::LightingPath::simd;
      o.isa = isa;
      o.pow_tier = tier;
      all.push_back({std::string("simd_") + facet::to_string(isa) + "_" + facet::to_string(tier), o});
      if (isa == facet::best_isa() && tier == facet::PowTier::automatic) sweep.push_back(all.back());
    }
  }
  auto add = [](const Method& m, Mix mix, int lights, int vertices, int threads = 0) {
    std::string name = "BM_Lighting/" + m.name + "/" + to_string(mix) + "/lights:" + std::to_string(lights) +
                       "/vertices:" + std::to_string(vertices);
    facet::LightingOptions options = m.options;
    if (threads > 0) {
      name += "/threads:" + std::to_string(threads);
      options.threads = threads;
    }
    auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
      run_lighting(state, options, mix, lights, vertices);
    });
    facet::bench::with_spread(b)->Unit(benchmark::kMillisecond);
    if (threads > 0) b->UseRealTime();  // the CPU timer sees only the calling thread
  };
  for (const Method& m : all)
    for (int vertices : {4096, 1 << 20}) add(m, Mix::mixed, 4, vertices);
  // The specular lobes side by side (the speed-against-accuracy chart's fourth panel): Blinn's n.h
  // and Phong's R.V, 4 mixed lights, 4096 vertices.
  for (const Method& m : all) {
    for (const bool phong : {false, true}) {
      const std::string name = "BM_LightingLobe/" + m.name + "/" + (phong ? "phong" : "blinn") + "/mixed/lights:4/vertices:4096";
      const facet::LightingOptions options = m.options;
      facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
        run_lighting(state, options, Mix::mixed, 4, 4096, phong);
      }))->Unit(benchmark::kMillisecond);
    }
  }
  // The lighting models side by side: GL's Blinn-Phong, glTF's GGX BRDF under the lights alone, and
  // under the lights and the neutral studio (image-based lighting per vertex).
  for (const Method& m : all) {
    if (m.options.path == facet::LightingPath::simd && m.options.pow_tier != facet::PowTier::automatic) continue;
    for (const char* model : {"gl", "pbr", "pbr_studio"}) {
      const std::string name = "BM_LightingModel/" + m.name + "/" + model + "/mixed/lights:4/vertices:65536";
      const facet::LightingOptions options = m.options;
      const bool pbr = std::string(model) != "gl", studio = std::string(model) == "pbr_studio";
      facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
        run_lighting(state, options, Mix::mixed, 4, 1 << 16, false, false, pbr, studio);
      }))->Unit(benchmark::kMillisecond);
    }
  }
  for (const Method& m : sweep)
    for (Mix mix : {Mix::mixed, Mix::directional, Mix::point, Mix::spot})
      for (int lights : {1, 4, 8, 16}) add(m, mix, lights, 1 << 16);
  for (const Method& m : sweep)
    for (int lights : {1, 4})
      for (int vertices : {1 << 16, 1 << 20})
        for (int threads : {1, 2}) add(m, Mix::point, lights, vertices, threads);
  // What a call costs without a Lighter: light_instance() makes its threads and memory each time.
  for (const Method& m : sweep) {
    if (m.options.path != facet::LightingPath::simd) continue;
    for (int threads : {1, 2}) {
      facet::LightingOptions options = m.options;
      options.threads = threads;
      const std::string name = "BM_LightingPerCall/" + m.name + "/point/lights:4/vertices:65536/threads:" + std::to_string(threads);
      facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
        run_lighting(state, options, Mix::point, 4, 1 << 16, false, true);
      }))->Unit(benchmark::kMillisecond)->UseRealTime();
    }
  }
}

}  // namespace

int main(int argc, char** argv) { return facet::bench::run_benchmarks(argc, argv, register_all); }
