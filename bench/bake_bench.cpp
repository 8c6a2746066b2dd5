// Baking (facet/bake.hpp): rays/s and radiosity shots/s of bake_lightmaps on the Cornell box, its
// emission alone lighting it (facet bake --lights none), at three lightmap densities (texels per
// millimetre x 1000), on 1 and 2 threads: the bake time against the number of patches and the
// thread scaling.
#include <benchmark/benchmark.h>

#include "context.hpp"

#include "facet/bake.hpp"
#include "repo_scenes.hpp"

namespace {

void BM_Bake(benchmark::State& state) {
  const auto scene = facet::load_scene_file(std::string(FACET_SOURCE_DIR) + "/tests/data/cornell/cornell.json", repo_scene_options());
  if (!scene) {
    state.SkipWithError(scene.status().message().c_str());
    return;
  }
  facet::BakeOptions o;
  o.charts.texels_per_unit = static_cast<double>(state.range(0)) / 1000.0;
  o.threads = static_cast<int>(state.range(1));
  o.direct = false;
  o.max_shots = 4000;
  double rays = 0, shots = 0;
  facet::BakeStats last;
  for (auto _ : state) {
    const facet::Result<facet::BakeResult> r = facet::bake_lightmaps(*scene, o);
    if (!r) {
      state.SkipWithError(r.status().message().c_str());
      return;
    }
    last = r->stats;
    rays += static_cast<double>(r->stats.rays);
    shots += static_cast<double>(r->stats.shots);
  }
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
  state.counters["shots/s"] = benchmark::Counter(shots, benchmark::Counter::kIsRate);
  state.counters["patches"] = static_cast<double>(last.patches);
  state.counters["texels"] = static_cast<double>(last.texels);
}
BENCHMARK(BM_Bake)->Apply([](benchmark::internal::Benchmark* b) { facet::bench::with_spread(b); })->ArgsProduct({{30, 60, 120}, {1, 2}})->ArgNames({"texels_per_m", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) { return facet::bench::run_static_benchmarks(argc, argv); }
