// Steady state allocates nothing: rendering the same scene at the same size a second time makes
// no call to operator new (replaced here, in this test binary only, by a counting one; libtbb's
// and the library's calls to operator new resolve to it too). The same replacement is a bounded
// allocator: with g_fail_above set, larger requests throw std::bad_alloc, and every API must then
// answer out_of_memory.
#include <atomic>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "facet/facet.h"
#include "facet/facet.hpp"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<std::size_t> g_fail_above{~std::size_t{0}};
}

// GCC 12 pairs the replaced operator new (it can throw now) with the free() below and warns of a
// mismatch that is not there: both sides of every pair are the ones defined here, on malloc.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (n > g_fail_above.load(std::memory_order_relaxed)) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (n > g_fail_above.load(std::memory_order_relaxed)) throw std::bad_alloc();
  const std::size_t al = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(al, (n + al - 1) / al * al)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) { return operator new(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace facet {
namespace {

// A scene with a large object (set up on slot 0, its chunks spread over the threads) beside
// runs of small ones (set up side by side, one task each, on whichever slot takes them), so that
// both kinds of per-slot scratch are exercised, and a dynamic environment's face passes.
// two_sided also sorts the blended glass sphere back to front (the frame plan's order keys).
Scene mixed_scene(bool two_sided) {
  Scene scene = make_default_scene();
  scene.two_sided = two_sided;
  if (two_sided) scene.transparent_order = TransparentOrder::back_to_front;
  scene.meshes.push_back({"big", make_uv_sphere(0.6f, 96, 48)});
  Instance big;
  big.mesh = static_cast<std::uint32_t>(scene.meshes.size() - 1);
  big.model(1, 3) = 1.5f;
  scene.objects.insert(scene.objects.begin() + 2, big);
  // A chrome ball with a dynamic cube map: six face passes and their textures every frame.
  Material chrome;
  chrome.environment.mode = EnvironmentMode::cube;
  chrome.environment.dynamic = true;
  chrome.environment.resolution = 24;
  chrome.environment.blend = EnvironmentBlend::mix;
  scene.materials.push_back(chrome);
  Instance ball;
  ball.mesh = big.mesh;
  ball.material = static_cast<std::uint32_t>(scene.materials.size() - 1);
  ball.model(0, 3) = -1.5f;
  scene.objects.push_back(ball);
  return scene;
}

// Which slot sets up which small object, and which worker joins the arena when, changes from
// frame to frame; after one frame no schedule may allocate. Two steady frames per case, with
// thread counts above the core count too: 96 schedules a run, and tools/stress runs this 200 times
// under load (20 in CI; five frames a case made each CI run of it take twice as long).
TEST(SteadyState, SecondFrameAllocatesNothing) {
  std::vector<std::uint8_t> pixels(320 * 200 * 4);
  std::vector<float> depth(320 * 200);
  const ImageView view{pixels.data(), 320, 200, 320 * 4, PixelFormat::rgba8, false};
  const DepthView depth_view{depth.data(), 320, 200, 320 * sizeof(float), false};
  for (bool two_sided : {false, true}) {
    const Scene scene = mixed_scene(two_sided);
    for (LightingPath path : {LightingPath::simd, LightingPath::scalar}) {
      for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
        for (int threads : {1, 2, 3, 8}) {
          Renderer renderer;
          RenderOptions o;
          o.shading = mode;
          o.path = path;
          o.threads = threads;
          FrameStats stats;
          ASSERT_TRUE(renderer.render(scene, o, view, &depth_view, &stats).ok());  // warms up
          const long before = g_allocations.load();
          for (int frame = 0; frame < 2; ++frame) {
            ASSERT_TRUE(renderer.render(scene, o, view, &depth_view, &stats).ok());
          }
          EXPECT_EQ(g_allocations.load() - before, 0)
              << to_string(mode) << ", " << to_string(path) << ", " << threads << " threads"
              << (two_sided ? ", two-sided" : "");
        }
      }
    }
  }
}

// Allocations above `bytes` fail while it lives.
struct BoundedAllocator {
  explicit BoundedAllocator(std::size_t bytes) { g_fail_above = bytes; }
  ~BoundedAllocator() { g_fail_above = ~std::size_t{0}; }
};

TEST(OutOfMemory, EveryEntryPointAnswersOutOfMemory) {
  Scene scene = make_default_scene();
  scene.meshes.push_back({"big", make_uv_sphere(1.0f, 512, 256)});  // 131k vertices: a 2 MB clip array
  scene.objects.push_back({static_cast<std::uint32_t>(scene.meshes.size() - 1), 0, Mat4::Identity()});
  std::vector<std::uint8_t> pixels(64 * 48 * 4, 0xA5);
  const ImageView view{pixels.data(), 64, 48, 64 * 4, PixelFormat::rgba8, false};
  for (int threads : {1, 2}) {
    std::fill(pixels.begin(), pixels.end(), std::uint8_t{0xA5});
    Renderer renderer;
    RenderOptions o;
    o.threads = threads;
    Status s;
    {
      BoundedAllocator bound(1 << 20);
      s = renderer.render(scene, o, view);
    }
    EXPECT_EQ(s.code(), ErrorCode::out_of_memory) << s.message();
    for (std::uint8_t b : pixels) ASSERT_EQ(b, 0xA5) << "a pixel was written";
    EXPECT_TRUE(renderer.render(scene, o, view).ok());  // and the renderer still works
  }
  {
    LightingOptions lo;
    VertexColors colours;
    BoundedAllocator bound(1 << 20);
    EXPECT_EQ(light_instance(scene, scene.objects.size() - 1, lo, colours).code(), ErrorCode::out_of_memory);
  }
  {
    std::string obj;
    for (int i = 0; i < 100000; ++i) obj += "v 0 0 " + std::to_string(i) + "\n";
    obj += "f 1 2 3\n";
    BoundedAllocator bound(1 << 20);
    const Result<Mesh> m = parse_obj(obj, "big.obj");
    EXPECT_EQ(m.status().code(), ErrorCode::out_of_memory) << m.status().message();
  }
  {
    BoundedAllocator bound(1 << 20);
    const Result<Scene> s = parse_scene_json(
        "{\"meshes\": [{\"name\": \"b\", \"shape\": \"sphere\", \"segments\": 512, \"rings\": 256}]}",
        "big.json", "");
    EXPECT_EQ(s.status().code(), ErrorCode::out_of_memory) << s.status().message();
  }
  {  // The C API
    const std::vector<float> sphere_xyz = [] {
      std::vector<float> xyz;
      const Mesh m = make_uv_sphere(1.0f, 512, 256);
      for (const Vec3& p : m.positions) xyz.insert(xyz.end(), {p.x(), p.y(), p.z() - 4.0f});
      return xyz;
    }();
    const Mesh m = make_uv_sphere(1.0f, 512, 256);
    std::vector<std::uint32_t> idx;
    for (const auto& t : m.triangles) idx.insert(idx.end(), t.begin(), t.end());
    facet_renderer* r = facet_renderer_create(nullptr, nullptr);
    facet_scene* cs = facet_scene_create();
    ASSERT_TRUE(r && cs);
    std::uint32_t mesh = 0, material = 0, object = 0;
    const facet_material mat = facet_material_default();
    const facet_light light = facet_light_default();
    ASSERT_EQ(facet_scene_add_mesh(cs, sphere_xyz.data(), m.vertex_count(), nullptr, idx.data(), m.triangle_count(), &mesh),
              FACET_OK);
    ASSERT_EQ(facet_scene_add_material(cs, &mat, &material), FACET_OK);
    ASSERT_EQ(facet_scene_add_object(cs, mesh, material, nullptr, &object), FACET_OK);
    ASSERT_EQ(facet_scene_add_light(cs, &light, NULL), FACET_OK);
    facet_status status = FACET_OK;
    {
      BoundedAllocator bound(1 << 20);
      status = facet_render(r, cs, pixels.data(), 64, 48, 64 * 4, FACET_RGBA8, 0, nullptr, 0, nullptr);
    }
    EXPECT_EQ(status, FACET_OUT_OF_MEMORY) << facet_renderer_last_error(r);
    facet_scene_destroy(cs);
    facet_renderer_destroy(r);
  }
}

}  // namespace
}  // namespace facet
