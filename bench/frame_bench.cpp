// Whole frames and pixel fill, with the thread count as an argument (each renderer owns its
// tbb::task_arena; UseRealTime because the work runs on TBB threads).
//   BM_Fill:  16 full-screen Gouraud layers at 1920x1080, depth test passing (front to back would
//             fail it: the layers are drawn back to front), no lighting cost to speak of.
//   BM_Frame: the built-in scene and, when ../shared/models exists, the Stanford bunny with 4
//             lights at 1920x1080, Gouraud, simd path on the best ISA.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "facet/facet.hpp"

namespace {

facet::Scene layers_scene(int layers) {
  facet::Scene s;
  s.camera.eye = facet::Vec3(0, 0, 0);
  s.camera.target = facet::Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 90;
  s.camera.far = 1000;
  facet::Mesh quad;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.normals.assign(4, facet::Vec3(0, 0, 1));
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.meshes.push_back({"quad", quad});
  facet::Material m;
  m.emissive = facet::Color3(0.3f, 0.5f, 0.7f);
  s.materials.push_back(m);
  for (int i = 0; i < layers; ++i) {  // back to front: every layer passes the depth test
    const float z = -50.0f + float(i);
    facet::Mat4 t = facet::Mat4::Identity();
    t.topLeftCorner<3, 3>() *= -z * 2.0f;  // large enough to cover the view at that depth
    t(2, 3) = z;
    s.objects.push_back({0, 0, t});
  }
  return s;
}

void run_frames(benchmark::State& state, const facet::Scene& scene, facet::RenderOptions options, int w, int h) {
  options.threads = static_cast<int>(state.range(0));
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * h * 4);
  const facet::ImageView view{pixels.data(), w, h, static_cast<std::size_t>(w) * 4, facet::PixelFormat::rgba8, false};
  facet::Renderer renderer;
  facet::FrameStats stats;
  for (auto _ : state) {
    const facet::Status s = renderer.render(scene, options, view, nullptr, &stats);
    if (!s.ok()) {
      state.SkipWithError(s.message().c_str());
      return;
    }
    benchmark::DoNotOptimize(pixels.data());
  }
  using benchmark::Counter;
  state.counters["frames/s"] = Counter(1.0, Counter::kIsIterationInvariantRate);
  state.counters["pixels_filled/s"] = Counter(double(stats.pixels_filled), Counter::kIsIterationInvariantRate);
  state.counters["vertices_lit/s"] = Counter(double(stats.vertices_lit), Counter::kIsIterationInvariantRate);
  state.SetLabel(std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(stats.threads) + " threads");
}

void BM_Fill(benchmark::State& state) {
  static const facet::Scene scene = layers_scene(16);
  run_frames(state, scene, {}, 1920, 1080);
}

void BM_Frame_Default(benchmark::State& state) {
  static const facet::Scene scene = facet::make_default_scene();
  run_frames(state, scene, {}, 1920, 1080);
}

void BM_Frame_Bunny(benchmark::State& state) {
  static const facet::Result<facet::Scene> scene =
      facet::load_scene_file(std::string(FACET_SOURCE_DIR) + "/tests/data/scenes/bunny.json");
  if (!scene) {
    state.SkipWithError(("bunny scene not available: " + scene.status().message()).c_str());
    return;
  }
  run_frames(state, *scene, {}, 1920, 1080);
}

void thread_args(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Fill)->Apply(thread_args);
BENCHMARK(BM_Frame_Default)->Apply(thread_args);
BENCHMARK(BM_Frame_Bunny)->Apply(thread_args);

}  // namespace

BENCHMARK_MAIN();
