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

TEST(SteadyState, SecondFrameAllocatesNothing) {
  const Scene scene = make_default_scene();
  std::vector<std::uint8_t> pixels(320 * 200 * 4);
  std::vector<float> depth(320 * 200);
  const ImageView view{pixels.data(), 320, 200, 320 * 4, PixelFormat::rgba8, false};
  const DepthView depth_view{depth.data(), 320, 200, 320 * sizeof(float), false};
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (int threads : {1, 2}) {
      Renderer renderer;
      RenderOptions o;
      o.shading = mode;
      o.threads = threads;
      FrameStats stats;
      ASSERT_TRUE(renderer.render(scene, o, view, &depth_view, &stats).ok());  // warms up
      ASSERT_TRUE(renderer.render(scene, o, view, &depth_view, &stats).ok());
      const long before = g_allocations.load();
      ASSERT_TRUE(renderer.render(scene, o, view, &depth_view, &stats).ok());
      EXPECT_EQ(g_allocations.load() - before, 0) << to_string(mode) << ", " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace facet
