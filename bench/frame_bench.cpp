// Whole frames and pixel fill (Google Benchmark; UseRealTime because the work runs on the
// renderer's own TBB threads; the thread count is the benchmark argument).
//   BM_Environment/<scene>/<shading>: environment maps per vertex (flat, Gouraud) and per pixel
//                       (Phong), static and dynamic (register_environment);
//   BM_Fill/<variant>/gouraud: 16 full-screen Gouraud layers at 1920x1080, drawn back to front so
//       every layer passes the depth test (33 M pixels a frame), no lighting cost to speak of;
//   BM_Fill/<variant>/phong:   4 full-screen layers lit per pixel (one point light);
//   BM_Fill/<variant>/small:   200,000 random triangles of 1-16 pixels at 1920x1080;
//   BM_Fill/<variant>/textured: the 16 Gouraud layers, each with a 256x256 trilinear texture
//       (GL_MODULATE, minified), lit by a directional light (separate specular);
//   BM_Fill/<variant>/textured_fog: the textured layers in linear fog (the fused modulate program
//       with fog);
//   BM_Fill/<variant>/blended:  the 16 Gouraud layers, each alpha-blended (alpha 0.5);
//   BM_Frame/<variant>/<scene>/<size>: the built-in scene and each model scene of
//       tests/data/scenes (skipped when ../shared/models is absent), Gouraud.
//   BM_Shadow/<method>/<scene>/1920x1080: the built-in scene and the bunny in Phong, with the
//       scene's first light shadowed by each method (none, map for each light type's 2048^2
//       pcf3x3 default, raycast) on the best ISA; shadows_ms is FrameStats::seconds_shadows (the
//       ray-cast hierarchy, or fitting and drawing the map); the lookups are in tiles_ms. The
//       method's share of the frame is (its frame time - none's) / its frame time.
// Variants: the scalar path (scalar lighting and rasterizer) and the simd path of each ISA this
// CPU has; the model scenes and 1280x720 run on the best ISA only.
// Counters: frames/s, pixels_filled/s, vertices_lit/s and bw_share, the bytes of the output
// image written per second over the triad bandwidth measured at start (bench/roofline.hpp), and
// the mean per-stage times of a frame (lighting_ms, geometry_ms, tiles_ms; FrameStats), and the
// resolve's thread time (resolve_ms) with its share of the image-store rate (resolve_share).
// --smoke draws every benchmark at a sixth of its width and height (the ctest smoke test).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "repo_scenes.hpp"
#include "facet/facet.hpp"
#include "fill_scenes.hpp"
#include "roofline.hpp"

namespace {

// `count` random triangles of 1-16 pixels each over a 1920x1080 view at depth -10.
facet::Scene small_triangles_scene(int count) {
  facet::Scene s;
  s.camera.eye = facet::Vec3(0, 0, 0);
  s.camera.target = facet::Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 90;
  s.camera.far = 100;
  std::mt19937 rng(3);
  // At depth 10 with a 90-degree field of view, 1080 pixels span 20 units: 1 px = 0.0185 units.
  std::uniform_real_distribution<float> x(-17.7f, 17.7f), y(-10.0f, 10.0f), side(0.027f, 0.1f), z(-11.0f, -9.0f);
  facet::Mesh m;
  for (int i = 0; i < count; ++i) {
    const facet::Vec3 c(x(rng), y(rng), z(rng));
    const float a = side(rng);  // right triangle with legs of 1.5 to 5.4 px: area 1-15 px
    m.positions.push_back(c);
    m.positions.push_back(c + facet::Vec3(a, 0, 0));
    m.positions.push_back(c + facet::Vec3(0, a, 0));
    for (int k = 0; k < 3; ++k) m.normals.push_back(facet::Vec3(0, 0, 1));
    const auto b = static_cast<std::uint32_t>(3 * i);
    m.triangles.push_back({b, b + 1, b + 2});
  }
  s.meshes.push_back({"small", m});
  facet::Material mat;
  mat.diffuse = facet::Color3(0.7f, 0.6f, 0.5f);
  s.materials.push_back(mat);
  s.objects.push_back({0, 0, facet::Mat4::Identity()});
  s.lights.push_back(facet::Light{});
  return s;
}

// --smoke (the ctest smoke test): every benchmark draws a sixth of its width and height, so that
// all of them run in seconds; their names keep the full size, their labels say the size drawn.
bool smoke = false;

void run_frames(benchmark::State& state, const facet::Scene& scene, facet::RenderOptions options, int w, int h) {
  if (smoke) w = std::max(w / 6, 16), h = std::max(h / 6, 16);
  options.threads = static_cast<int>(state.range(0));
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * h * 4);
  const facet::ImageView view{pixels.data(), w, h, static_cast<std::size_t>(w) * 4, facet::PixelFormat::rgba8, false};
  facet::Renderer renderer;
  facet::FrameStats stats;
  double lighting = 0, geometry = 0, tiles = 0, resolve = 0, shadows = 0;  // seconds, summed over frames
  // One frame first: the renderer's scratch (and shadow maps) are allocated, the steady state
  // is what is timed.
  if (const facet::Status s = renderer.render(scene, options, view, nullptr, &stats); !s.ok()) {
    state.SkipWithError(s.message().c_str());
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const facet::Status s = renderer.render(scene, options, view, nullptr, &stats);
    if (!s.ok()) {
      state.SkipWithError(s.message().c_str());
      return;
    }
    benchmark::DoNotOptimize(pixels.data());
    lighting += stats.seconds_lighting, geometry += stats.seconds_geometry, tiles += stats.seconds_raster;
    resolve += stats.seconds_resolve, shadows += stats.seconds_shadows;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  using benchmark::Counter;
  state.counters["frames/s"] = Counter(1.0, Counter::kIsIterationInvariantRate);
  state.counters["pixels_filled/s"] = Counter(double(stats.pixels_filled), Counter::kIsIterationInvariantRate);
  state.counters["vertices_lit/s"] = Counter(double(stats.vertices_lit), Counter::kIsIterationInvariantRate);
  state.counters["threads"] = stats.threads;
  // Per-stage milliseconds a frame (FrameStats; lighting and geometry are thread time summed over
  // objects set up side by side, tiles is wall time).
  const double frames = double(state.iterations());
  state.counters["lighting_ms"] = 1e3 * lighting / frames;
  state.counters["geometry_ms"] = 1e3 * geometry / frames;
  state.counters["tiles_ms"] = 1e3 * tiles / frames;
  state.counters["shadows_ms"] = 1e3 * shadows / frames;
  // Resolve: thread time a frame, and the image bytes it wrote per second of it over the rate of
  // filling the same image with plain stores (roofline image_store; 1 = at memory speed).
  state.counters["resolve_ms"] = 1e3 * resolve / frames;
  if (resolve > 0) {
    state.counters["resolve_share"] =
        frames * double(pixels.size()) / resolve / facet::bench::roofline().image_store_bytes_per_s;
  }
  state.counters["bw_share"] = double(state.iterations()) * double(pixels.size()) / seconds /
                               facet::bench::roofline().triad_bytes_per_s;
  state.SetLabel(std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(stats.threads) + " threads");
}

// A variant: the scalar path (scalar lighting and the scalar rasterizer) or the simd path on one ISA.
struct Variant {
  const char* name;
  facet::LightingPath path;
  facet::Isa isa;
};
constexpr Variant kVariants[] = {{"scalar", facet::LightingPath::scalar, facet::Isa::best},
                                 {"sse2", facet::LightingPath::simd, facet::Isa::sse2},
                                 {"avx2", facet::LightingPath::simd, facet::Isa::avx2},
                                 {"avx512", facet::LightingPath::simd, facet::Isa::avx512}};

// A scene file of tests/data/scenes, loaded once; null (with the reason) when its model is absent.
const facet::Scene* scene_file(const std::string& name, std::string& error) {
  static std::vector<std::pair<std::string, facet::Result<facet::Scene>>> cache;
  for (auto& [n, r] : cache) {
    if (n == name) {
      if (!r) error = r.status().message();
      return r ? &*r : nullptr;
    }
  }
  cache.emplace_back(name, facet::load_scene_file(std::string(FACET_SOURCE_DIR) + "/tests/data/scenes/" + name + ".json", repo_scene_options()));
  return scene_file(name, error);
}

void add(const std::string& name, std::function<void(benchmark::State&)> fn) {
  facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), std::move(fn)))
      ->ArgName("threads")
      ->Arg(1)
      ->Arg(2)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

void register_shadows() {
  facet::RenderOptions phong;
  phong.shading = facet::ShadingMode::phong;
  for (const char* scene_name : {"default", "bunny"}) {
    for (const facet::ShadowMethod method : {facet::ShadowMethod::none, facet::ShadowMethod::map, facet::ShadowMethod::volume,
                                             facet::ShadowMethod::raycast}) {
      const std::string name = std::string("BM_Shadow/") + facet::to_string(method) + "/" + scene_name + "/1920x1080";
      add(name, [phong, method, scene_name](benchmark::State& state) {
        std::string error;
        const facet::Scene* loaded = nullptr;
        static const facet::Scene built_in = facet::make_default_scene();
        if (std::string(scene_name) == "default") {
          loaded = &built_in;
        } else if (!(loaded = scene_file(scene_name, error))) {
          state.SkipWithError(("model not available: " + error).c_str());
          return;
        }
        facet::Scene scene = *loaded;
        scene.lights.front().shadow.method = method;
        run_frames(state, scene, phong, 1920, 1080);
      });
    }
  }
}

// Environment maps at 1920x1080 on the best ISA: per vertex (flat, Gouraud: texgen at the
// vertices) against per pixel (Phong), on three balls with a cube, a sphere and a normal map
// (environment), and a chrome ball with a dynamic cube map in a room (reflections; its six face
// passes included).
void register_environment() {
  for (const char* scene_name : {"environment", "reflections"}) {
    for (const facet::ShadingMode shading : {facet::ShadingMode::flat, facet::ShadingMode::gouraud, facet::ShadingMode::phong}) {
      facet::RenderOptions o;
      o.shading = shading;
      add(std::string("BM_Environment/") + scene_name + "/" + facet::to_string(shading) + "/1920x1080",
          [o, scene_name](benchmark::State& state) {
            std::string error;
            const facet::Scene* scene = scene_file(scene_name, error);
            if (!scene) {
              state.SkipWithError(error.c_str());
              return;
            }
            run_frames(state, *scene, o, 1920, 1080);
          });
    }
  }
}

void register_all() {
  register_shadows();
  register_environment();
  const std::vector<std::string> models = {"bunny", "teapot", "suzanne", "spot", "fandisk"};
  for (const Variant& v : kVariants) {
    if (v.path == facet::LightingPath::simd && !facet::isa_supported(v.isa)) continue;
    const bool best = v.path == facet::LightingPath::simd && v.isa == facet::best_isa();
    facet::RenderOptions o;
    o.path = v.path;
    o.isa = v.isa;
    const std::string prefix = std::string("/") + v.name + "/";
    add("BM_Fill" + prefix + "gouraud", [o](benchmark::State& state) {
      static const facet::Scene scene = facet::bench::layers_scene(16);
      run_frames(state, scene, o, 1920, 1080);
    });
    add("BM_Fill" + prefix + "textured", [o](benchmark::State& state) {
      static const facet::Scene scene = facet::bench::layers_scene(16, false, facet::bench::Layers::textured);
      run_frames(state, scene, o, 1920, 1080);
    });
    add("BM_Fill" + prefix + "textured_fog", [o](benchmark::State& state) {
      static const facet::Scene scene = facet::bench::layers_scene(16, false, facet::bench::Layers::textured_fog);
      run_frames(state, scene, o, 1920, 1080);
    });
    if (v.path == facet::LightingPath::simd) {  // the 16-bit pixel tier (pixel_precision fast) on the textured layers
      facet::RenderOptions fast = o;
      fast.pixel_precision = facet::PixelPrecision::fast;
      add("BM_Fill" + prefix + "textured_fast", [fast](benchmark::State& state) {
        static const facet::Scene scene = facet::bench::layers_scene(16, false, facet::bench::Layers::textured);
        run_frames(state, scene, fast, 1920, 1080);
      });
      add("BM_Fill" + prefix + "textured_fog_fast", [fast](benchmark::State& state) {
        static const facet::Scene scene = facet::bench::layers_scene(16, false, facet::bench::Layers::textured_fog);
        run_frames(state, scene, fast, 1920, 1080);
      });
    }
    add("BM_Fill" + prefix + "blended", [o](benchmark::State& state) {
      static const facet::Scene scene = facet::bench::layers_scene(16, false, facet::bench::Layers::blended);
      run_frames(state, scene, o, 1920, 1080);
    });
    facet::RenderOptions phong = o;
    phong.shading = facet::ShadingMode::phong;
    add("BM_Fill" + prefix + "phong", [phong](benchmark::State& state) {
      static const facet::Scene scene = facet::bench::layers_scene(4, true);
      run_frames(state, scene, phong, 1920, 1080);
    });
    add("BM_Fill" + prefix + "small", [o](benchmark::State& state) {
      static const facet::Scene scene = small_triangles_scene(200000);
      run_frames(state, scene, o, 1920, 1080);
    });
    for (const char* size : {"1280x720", "1920x1080"}) {
      const int w = size[0] == '1' && size[1] == '2' ? 1280 : 1920, h = w == 1280 ? 720 : 1080;
      if (w == 1280 && !best) continue;
      add("BM_Frame" + prefix + "default/" + size, [o, w, h](benchmark::State& state) {
        static const facet::Scene scene = facet::make_default_scene();
        run_frames(state, scene, o, w, h);
      });
      for (const std::string& model : models) {
        if (!best && model != "bunny") continue;
        add("BM_Frame" + prefix + model + "/" + size, [o, w, h, model](benchmark::State& state) {
          std::string error;
          const facet::Scene* scene = scene_file(model, error);
          if (!scene) {
            state.SkipWithError(("model not available: " + error).c_str());
            return;
          }
          run_frames(state, *scene, o, w, h);
        });
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--smoke") {
      smoke = true;
    } else {
      argv[kept++] = argv[i];
    }
  }
  return facet::bench::run_benchmarks(kept, argv, register_all);
}
