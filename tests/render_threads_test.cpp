// Determinism: images and depth are byte-identical for any thread count, in every shading mode, on
// the built-in scene and on a scene of 10^5 small random triangles. And the SIMD rasterizer of
// every ISA against the scalar one on the same scenes: identical coverage, colour within 1 step.
#include <cstdio>
#include <random>
#include <thread>

#include <unistd.h>
#if !defined(FACET_STD_THREADS)
#include <tbb/info.h>
#endif

#include "facet/facet.h"

#include "render_support.hpp"

namespace facet {
namespace {

Scene random_triangles_scene(int count) {
  Scene s = test::camera_scene();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-6.0f, 6.0f), depth(-12.0f, -4.0f), off(-0.25f, 0.25f);
  Mesh m;
  for (int i = 0; i < count; ++i) {
    const Vec3 c(pos(rng), pos(rng), depth(rng));
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(c + Vec3(off(rng), off(rng), off(rng)));
      m.normals.push_back(Vec3(off(rng), off(rng), 1.0f).normalized());
    }
    const auto b = static_cast<std::uint32_t>(3 * i);
    m.triangles.push_back({b, b + 1, b + 2});
  }
  s.meshes.push_back({"soup", m});
  Material mat;
  mat.diffuse = Color3(0.8f, 0.6f, 0.4f);
  mat.specular = Color3(0.5f, 0.5f, 0.5f);
  mat.shininess = 20;
  s.materials.push_back(mat);
  s.objects.push_back({0, 0, Mat4::Identity()});
  Light l;
  l.type = LightType::point;
  l.position = Vec3(2, 3, 0);
  s.lights.push_back(l);
  s.lights.push_back(Light{});
  return s;
}

// What a frame can really run on: the request, capped by the hardware threads (TBB's default
// limit) except in the std::thread build of the tsan preset, which starts every thread asked for.
int threads_that_run(int requested) {
#if defined(FACET_STD_THREADS)
  return requested;
#else
  return std::min(requested, tbb::info::default_concurrency());
#endif
}

void expect_same_for_any_thread_count(const Scene& s, int w, int h) {
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    std::vector<std::uint8_t> first_pixels;
    std::vector<float> first_depth;
    for (int threads : {1, 2, 3, 8}) {
      test::Canvas c(w, h);
      std::vector<float> depth(static_cast<std::size_t>(w * h));
      const DepthView d{depth.data(), w, h, static_cast<std::size_t>(w) * sizeof(float), false};
      RenderOptions o;
      o.shading = mode;
      o.threads = threads;
      o.tile_size = 32;
      FrameStats st;
      Renderer r;
      ASSERT_TRUE(r.render(s, o, c.view(), &d, &st).ok());
      EXPECT_EQ(st.threads, threads_that_run(threads));
      if (first_pixels.empty()) {
        first_pixels = c.pixels();
        first_depth = depth;
        EXPECT_GT(st.pixels_filled, 0u);
      } else {
        EXPECT_TRUE(c.pixels() == first_pixels) << to_string(mode) << ", " << threads << " threads";
        EXPECT_TRUE(depth == first_depth) << to_string(mode) << ", " << threads << " threads";
      }
    }
  }
}

TEST(RenderThreads, BuiltInSceneIsByteIdenticalForAnyThreadCount) {
  expect_same_for_any_thread_count(make_default_scene(), 320, 200);
}

TEST(RenderThreads, HundredThousandSmallTrianglesAreByteIdenticalForAnyThreadCount) {
  expect_same_for_any_thread_count(random_triangles_scene(100000), 256, 160);
}

struct ThreadFrame {
  std::vector<std::uint8_t> pixels;
  std::vector<float> depth;
};

ThreadFrame render_frame(const Scene& s, int w, int h, ShadingMode mode, LightingPath path, Isa isa) {
  test::Canvas c(w, h);
  ThreadFrame f{{}, std::vector<float>(static_cast<std::size_t>(w * h))};
  const DepthView d{f.depth.data(), w, h, static_cast<std::size_t>(w) * sizeof(float), false};
  RenderOptions o;
  o.shading = mode;
  o.path = path;
  o.isa = isa;
  o.tile_size = 24;  // blocks of 8 that do not divide the image
  Renderer r;
  EXPECT_TRUE(r.render(s, o, c.view(), &d).ok());
  EXPECT_TRUE(c.outside_pixels_untouched());
  f.pixels = c.pixels();
  return f;
}

void expect_same_coverage_on_every_isa(const Scene& s, int w, int h) {
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    const ThreadFrame scalar = render_frame(s, w, h, mode, LightingPath::scalar, Isa::best);
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      const ThreadFrame simd = render_frame(s, w, h, mode, LightingPath::simd, isa);
      std::size_t coverage_differs = 0, covered = 0;
      int worst = 0;
      for (std::size_t i = 0; i < scalar.depth.size(); ++i) {
        coverage_differs += (scalar.depth[i] < 1.0f) != (simd.depth[i] < 1.0f);
        covered += simd.depth[i] < 1.0f;
      }
      for (std::size_t i = 0; i < scalar.pixels.size(); ++i) worst = std::max(worst, std::abs(scalar.pixels[i] - simd.pixels[i]));
      EXPECT_EQ(coverage_differs, 0u) << to_string(mode) << ", " << to_string(isa);
      EXPECT_LE(worst, 1) << to_string(mode) << ", " << to_string(isa);
      EXPECT_GT(covered, scalar.depth.size() / 20);
    }
  }
}

TEST(RenderPaths, BuiltInSceneHasTheSameCoverageOnEveryIsa) { expect_same_coverage_on_every_isa(make_default_scene(), 333, 201); }

TEST(RenderPaths, SmallTrianglesHaveTheSameCoverageOnEveryIsa) {
  expect_same_coverage_on_every_isa(random_triangles_scene(100000), 250, 161);
}

// Embedding: two renderers in two threads render two scenes at the same time (and a third thread
// renders the first scene again with a third renderer); every image equals the one rendered alone.
TEST(RenderThreads, RenderersInDifferentThreadsRenderConcurrently) {
  const Scene a = make_default_scene();
  const Scene b = random_triangles_scene(20000);
  const int w = 160, h = 120;
  RenderOptions config;
  config.threads = 2;
  config.shading = ShadingMode::phong;
  auto render_alone = [&](const Scene& s) {
    test::Canvas c(w, h);
    Renderer r(config);
    EXPECT_TRUE(r.render(s, c.view()).ok());
    return c.pixels();
  };
  const std::vector<std::uint8_t> expected_a = render_alone(a), expected_b = render_alone(b);
  for (int round = 0; round < 3; ++round) {
    test::Canvas ca(w, h), cb(w, h), cc(w, h);
    Status sa, sb, sc;
    {
      std::jthread ta([&] { Renderer r(config); for (int i = 0; i < 3; ++i) sa = r.render(a, ca.view()); });
      std::jthread tb([&] { Renderer r(config); for (int i = 0; i < 3; ++i) sb = r.render(b, cb.view()); });
      std::jthread tc([&] { Renderer r(config); for (int i = 0; i < 3; ++i) sc = r.render(a, cc.view()); });
    }
    EXPECT_TRUE(sa.ok() && sb.ok() && sc.ok());
    EXPECT_TRUE(ca.pixels() == expected_a);
    EXPECT_TRUE(cb.pixels() == expected_b);
    EXPECT_TRUE(cc.pixels() == expected_a);
  }
}

TEST(RenderThreads, ConfiguredRendererUsesItsConfigAndReportsStats) {
  RenderOptions config;
  config.threads = 1;
  config.tile_size = 16;
  Renderer r(config);
  EXPECT_EQ(r.config().tile_size, 16);
  EXPECT_EQ(r.last_stats().threads, 0);
  test::Canvas c(40, 30);
  ASSERT_TRUE(r.render(make_default_scene(), c.view()).ok());
  EXPECT_EQ(r.last_stats().threads, 1);
  EXPECT_GT(r.last_stats().pixels_filled, 0u);
  config.tile_size = 12;
  EXPECT_EQ(check_render_options(config).field(), "options.tile_size");
  r.set_config(config);
  test::Canvas untouched(40, 30);
  EXPECT_EQ(r.render(make_default_scene(), untouched.view()).field(), "options.tile_size");
  EXPECT_TRUE(untouched.untouched());
}

// More threads than cores: libtbb would print "TBB Warning: The number of workers is currently
// limited..." to stderr (once per process, so this test needs its own process, as ctest gives
// it); the library prints nothing, through the C++ and the C API, and reports what ran.
TEST(RenderThreads, MoreThreadsThanCoresPrintsNothing) {
  std::fflush(stderr);
  std::fflush(stdout);
  std::FILE* sink = std::tmpfile();
  ASSERT_NE(sink, nullptr);
  const int saved_err = dup(2), saved_out = dup(1);
  ASSERT_GE(saved_err, 0);
  dup2(fileno(sink), 2);
  dup2(fileno(sink), 1);
  const int many = std::min(256, 4 * std::max(2, static_cast<int>(std::thread::hardware_concurrency())));
  test::Canvas c(64, 48);
  RenderOptions o;
  o.threads = many;
  FrameStats st;
  Renderer r;
  const Status rendered = r.render(make_default_scene(), o, c.view(), nullptr, &st);
  LightingOptions lo;
  lo.threads = many;
  VertexColors colours;
  const Status lit = light_instance(make_default_scene(), 0, lo, colours);
  facet_render_config cc = facet_render_config_default();
  cc.threads = many;
  facet_status cstatus = FACET_OK;
  facet_renderer* cr = facet_renderer_create(&cc, &cstatus);
  facet_scene* cs = facet_scene_create();
  int c_status = cr && cs ? FACET_OK : -1;
  if (c_status == FACET_OK) {
    const float positions[9] = {-1, -1, -5, 1, -1, -5, 0, 1, -5};
    const std::uint32_t indices[3] = {0, 1, 2};
    std::uint32_t mesh = 0, material = 0, object = 0;
    const facet_material m = facet_material_default();
    const facet_light l = facet_light_default();
    c_status = facet_scene_add_mesh(cs, positions, 3, nullptr, indices, 1, &mesh);
    if (c_status == FACET_OK) c_status = facet_scene_add_material(cs, &m, &material);
    if (c_status == FACET_OK) c_status = facet_scene_add_object(cs, mesh, material, nullptr, &object);
    if (c_status == FACET_OK) c_status = facet_scene_add_light(cs, &l, NULL);
    std::vector<std::uint8_t> px(64 * 48 * 4);
    if (c_status == FACET_OK) {
      c_status = facet_render(cr, cs, px.data(), 64, 48, 64 * 4, FACET_RGBA8, 0, nullptr, 0, nullptr);
    }
  }
  facet_scene_destroy(cs);
  facet_renderer_destroy(cr);
  std::fflush(stderr);
  std::fflush(stdout);
  dup2(saved_err, 2);
  dup2(saved_out, 1);
  close(saved_err);
  close(saved_out);
  std::string printed;
  std::rewind(sink);
  for (int ch; (ch = std::fgetc(sink)) != EOF;) printed += static_cast<char>(ch);
  std::fclose(sink);
  ASSERT_TRUE(rendered.ok()) << rendered.message();
  ASSERT_TRUE(lit.ok()) << lit.message();
  ASSERT_EQ(c_status, FACET_OK);
  EXPECT_EQ(printed, "");
  EXPECT_EQ(st.threads, threads_that_run(many));
}

// Coincident faces of one large object: two full-screen quads at the same depth, with different
// normals (so different colours), 6000 triangles apart, so in different set-up ranges that
// different threads set up. Depth test LESS keeps the first one submitted, so the image must be
// that quad's colour, whatever the thread count (a bin merge ordered by worker slot would not be).
Mesh coincident_quads(bool red_first) {
  Mesh m;
  auto quad = [&](const Vec3& normal) {
    const auto b = static_cast<std::uint32_t>(m.positions.size());
    for (const Vec3& p : {Vec3(-9, -9, -5), Vec3(9, -9, -5), Vec3(9, 9, -5), Vec3(-9, 9, -5)}) {
      m.positions.push_back(p);
      m.normals.push_back(normal.normalized());
    }
    m.triangles.push_back({b, b + 1, b + 2});
    m.triangles.push_back({b, b + 2, b + 3});
  };
  const Vec3 toward_red(-1, 0, 1), toward_blue(1, 0, 1);
  quad(red_first ? toward_red : toward_blue);
  // Filler: tiny triangles far outside the view, so the second quad lands in range 2 or later.
  for (int i = 0; i < 6000; ++i) {
    const auto b = static_cast<std::uint32_t>(m.positions.size());
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(Vec3(100.0f + float(k), 100.0f + float(i % 7), -5.0f));
      m.normals.push_back(Vec3(0, 0, 1));
    }
    m.triangles.push_back({b, b + 1, b + 2});
  }
  quad(red_first ? toward_blue : toward_red);
  return m;
}

TEST(RenderThreads, CoincidentFacesInDifferentRangesKeepSubmissionOrder) {
  for (bool red_first : {true, false}) {
    Scene s = test::camera_scene();
    s.meshes.push_back({"quads", coincident_quads(red_first)});
    Material mat;
    mat.diffuse = Color3(1, 1, 1);
    s.materials.push_back(mat);
    s.objects.push_back({0, 0, Mat4::Identity()});
    Light red, blue;
    red.direction = Vec3(1, 0, -1);  // travels to +x: lights the quad whose normal is toward_red
    red.diffuse = Color3(1, 0, 0);
    blue.direction = Vec3(-1, 0, -1);
    blue.diffuse = Color3(0, 0, 1);
    s.lights = {red, blue};
    // Flat shading lights the geometric face normal, the same for both quads: only the vertex
    // normals of Gouraud and Phong tell them apart.
    struct Case {
      ShadingMode mode;
      LightingPath path;
    };
    for (const auto& [mode, path] : {Case{ShadingMode::gouraud, LightingPath::scalar}, Case{ShadingMode::gouraud, LightingPath::simd},
                                     Case{ShadingMode::phong, LightingPath::scalar}, Case{ShadingMode::phong, LightingPath::simd}}) {
      for (int threads : {1, 2, 3, 8}) {
        test::Canvas c(96, 64);
        RenderOptions o;
        o.shading = mode;
        o.path = path;
        o.threads = threads;
        o.tile_size = 16;
        Renderer r;
        ASSERT_TRUE(r.render(s, o, c.view()).ok());
        const std::vector<std::uint8_t> px = c.pixels();
        int first_wins = 0;
        for (std::size_t i = 0; i < px.size(); i += 4) {
          const bool is_red = px[i] > 100 && px[i + 2] < 20, is_blue = px[i + 2] > 100 && px[i] < 20;
          first_wins += red_first ? is_red : is_blue;
        }
        EXPECT_EQ(first_wins, 96 * 64) << to_string(mode) << ", " << to_string(path) << ", " << threads << " threads, "
                                       << (red_first ? "red" : "blue") << " first";
      }
    }
  }
}

TEST(RenderThreads, ThreadCountIsChecked) {
  test::Canvas c(8, 8);
  RenderOptions o;
  o.threads = -1;
  Renderer r;
  EXPECT_EQ(r.render(make_default_scene(), o, c.view()).field(), "options.threads");
  EXPECT_TRUE(c.untouched());
}

}  // namespace
}  // namespace facet
