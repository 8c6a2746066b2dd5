// Steady state allocates nothing: rendering the same scene at the same size a second time makes
// no call to operator new (replaced here, in this test binary only, by a counting one; libtbb's
// and the library's calls to operator new resolve to it too).
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "facet/facet.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
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
// both kinds of per-slot scratch are exercised.
Scene mixed_scene(bool two_sided) {
  Scene scene = make_default_scene();
  scene.two_sided = two_sided;
  scene.meshes.push_back({"big", make_uv_sphere(0.6f, 96, 48)});
  Instance big;
  big.mesh = static_cast<std::uint32_t>(scene.meshes.size() - 1);
  big.model(1, 3) = 1.5f;
  scene.objects.insert(scene.objects.begin() + 2, big);
  return scene;
}

// Which slot sets up which small object, and which worker joins the arena when, changes from
// frame to frame; after one frame no schedule may allocate. Five steady frames per case, with
// thread counts above the core count too (tools/stress runs this 200 times under load).
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
          for (int frame = 0; frame < 5; ++frame) {
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

}  // namespace
}  // namespace facet
