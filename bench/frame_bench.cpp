// Whole frames and pixel fill, with the thread count as an argument (each renderer owns its
// tbb::task_arena; UseRealTime because the work runs on TBB threads).
//   BM_Fill:  16 full-screen Gouraud layers at 1920x1080, depth test passing (front to back would
//             fail it: the layers are drawn back to front), no lighting cost to speak of.
//   BM_Frame: the built-in scene and, when ../shared/models exists, the Stanford bunny with 4
//             lights at 1920x1080, Gouraud.
// Each on the scalar path and on the simd path of every ISA this CPU has (BM_Fill/avx2/threads:2).
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

// A rasterizer variant: the scalar path (scalar lighting and the scalar rasterizer) or the simd
// path on one ISA.
struct Variant {
  const char* name;
  facet::LightingPath path;
  facet::Isa isa;
};
constexpr Variant kVariants[] = {{"scalar", facet::LightingPath::scalar, facet::Isa::best},
                                 {"sse2", facet::LightingPath::simd, facet::Isa::sse2},
                                 {"avx2", facet::LightingPath::simd, facet::Isa::avx2},
                                 {"avx512", facet::LightingPath::simd, facet::Isa::avx512}};

const facet::Scene* bunny_scene(std::string& error) {
  static const facet::Result<facet::Scene> scene =
      facet::load_scene_file(std::string(FACET_SOURCE_DIR) + "/tests/data/scenes/bunny.json");
  if (!scene) {
    error = "bunny scene not available: " + scene.status().message();
    return nullptr;
  }
  return &*scene;
}

void register_all() {
  for (const Variant& v : kVariants) {
    if (v.path == facet::LightingPath::simd && !facet::isa_supported(v.isa)) continue;
    facet::RenderOptions o;
    o.path = v.path;
    o.isa = v.isa;
    auto add = [&](const std::string& name, auto&& fn) {
      benchmark::RegisterBenchmark(name.c_str(), fn)
          ->ArgName("threads")
          ->Arg(1)
          ->Arg(2)
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond);
    };
    add(std::string("BM_Fill/") + v.name, [o](benchmark::State& state) {
      static const facet::Scene scene = layers_scene(16);
      run_frames(state, scene, o, 1920, 1080);
    });
    add(std::string("BM_Frame_Default/") + v.name, [o](benchmark::State& state) {
      static const facet::Scene scene = facet::make_default_scene();
      run_frames(state, scene, o, 1920, 1080);
    });
    add(std::string("BM_Frame_Bunny/") + v.name, [o](benchmark::State& state) {
      std::string error;
      const facet::Scene* scene = bunny_scene(error);
      if (!scene) {
        state.SkipWithError(error.c_str());
        return;
      }
      run_frames(state, *scene, o, 1920, 1080);
    });
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
