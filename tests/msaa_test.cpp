// Multisampling (RenderOptions::samples): coverage against the exact area of each pixel under a
// triangle, watertight shared edges per sample, the same coverage on every path and ISA, the
// resolve in linear colour, the same bytes for any thread count, and the option's validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "render_support.hpp"

namespace facet {
namespace {

using test::Canvas;

constexpr int kSide = 64;

// The point (x, y, -1) seen by test::camera_scene's camera (90-degree field of view) at screen
// position (sx, sy) (pixels, y down) of a kSide x kSide image.
std::array<float, 2> to_world(double sx, double sy) {
  return {static_cast<float>(2.0 * sx / kSide - 1.0), static_cast<float>(1.0 - 2.0 * sy / kSide)};
}

// A triangle at depth 1 in front of test::camera_scene's camera, emissive `colour`, from screen
// positions.
void add_screen_triangle(Scene& s, const std::array<std::array<double, 2>, 3>& p, const Color3& colour) {
  Mesh m;
  for (const auto& q : p) {
    const auto w = to_world(q[0], q[1]);
    m.positions.emplace_back(w[0], w[1], -1.0f);
  }
  m.normals.assign(3, Vec3(0, 0, 1));
  m.triangles = {{0, 1, 2}};
  test::add_emissive(s, std::move(m), colour);
}

// The area of the triangle p inside the unit square at (x, y): the triangle clipped by the
// square's four half-planes (Sutherland-Hodgman), then the shoelace formula.
double area_in_pixel(const std::array<std::array<double, 2>, 3>& p, int x, int y) {
  std::vector<std::array<double, 2>> poly(p.begin(), p.end());
  const auto clip = [&](int axis, double bound, bool keep_above) {
    std::vector<std::array<double, 2>> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      const bool ina = keep_above ? a[axis] >= bound : a[axis] <= bound;
      const bool inb = keep_above ? b[axis] >= bound : b[axis] <= bound;
      if (ina) out.push_back(a);
      if (ina != inb) {
        const double t = (bound - a[axis]) / (b[axis] - a[axis]);
        out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
      }
    }
    poly = out;
  };
  clip(0, x, true), clip(0, x + 1, false), clip(1, y, true), clip(1, y + 1, false);
  double area = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    area += a[0] * b[1] - b[0] * a[1];
  }
  return std::abs(area) / 2;
}

RenderOptions options_for(int samples, LightingPath path = LightingPath::simd, Isa isa = Isa::best) {
  RenderOptions o;
  o.samples = samples;
  o.path = path;
  o.isa = isa;
  o.cull = CullMode::none;
  o.shading = ShadingMode::flat;
  o.clear_color = {0.0f, 0.0f, 0.0f, 0.0f};
  return o;
}

// Each pixel's resolved coverage of a white triangle on black (float output: the covered share of
// its samples) against the exact area of the pixel under the triangle, on random triangles: the
// mean error over the pixels either one touches falls as the sample count grows, and the sum over
// the image matches the triangle's area.
TEST(Msaa, CoverageApproachesTheExactAreaOfEachPixel) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(2.0, kSide - 2.0);
  double previous_mean = 1e9;
  for (int samples : {1, 4, 8, 16}) {
    double sum_error = 0, worst = 0, area_total = 0, coverage_total = 0;
    std::size_t pixels = 0;
    for (int trial = 0; trial < 40; ++trial) {
      std::array<std::array<double, 2>, 3> p;
      for (auto& q : p) q = {coord(rng), coord(rng)};
      // Positions snapped to 1/256 pixel first, as the raster snaps them (no error from snapping).
      for (auto& q : p) q = {std::round(q[0] * 256) / 256, std::round(q[1] * 256) / 256};
      Scene s = test::camera_scene();
      add_screen_triangle(s, p, Color3(1, 1, 1));
      Canvas c(kSide, kSide, PixelFormat::rgba32f);
      Renderer r;
      ASSERT_TRUE(r.render(s, options_for(samples), c.view()).ok());
      for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
          const double area = area_in_pixel(p, x, y), got = c.channel_f(x, y, 0);
          if (area == 0 && got == 0) continue;
          ++pixels;
          sum_error += std::abs(got - area);
          worst = std::max(worst, std::abs(got - area));
          area_total += area, coverage_total += got;
          // The resolved value is a whole number of samples over the count.
          ASSERT_EQ(got * samples, std::round(got * samples)) << samples << " samples, pixel " << x << ", " << y;
        }
      }
    }
    const double mean = sum_error / double(pixels), total = std::abs(coverage_total - area_total) / area_total;
    std::printf("%2d samples: mean |coverage - area| %.4f, largest %.3f over %zu pixels; total coverage off by %.4f %%\n",
                samples, mean, worst, pixels, 100 * total);
    // Measured: mean 0.061 / 0.027 / 0.016 / 0.010 and largest 0.90 / 0.40 / 0.29 / 0.17 for
    // 1 / 4 / 8 / 16 samples; the total within 0.2 %.
    const double mean_bound = samples == 1 ? 0.08 : samples == 4 ? 0.038 : samples == 8 ? 0.023 : 0.014;
    const double worst_bound = samples == 1 ? 1.0 : samples == 4 ? 0.5 : samples == 8 ? 0.36 : 0.25;
    EXPECT_LT(mean, previous_mean) << samples;
    EXPECT_LT(mean, mean_bound) << samples;
    EXPECT_LT(worst, worst_bound) << samples;
    EXPECT_LT(total, 0.005) << samples;
    previous_mean = mean;
  }
}

// Shared edges are watertight per sample: a fan of triangles around an inner point, blended
// additively (no depth writes), covers every sample of the pixels inside it exactly once, so each
// of those pixels resolves to exactly the one layer's value; on every path and ISA and with each
// sample count.
TEST(Msaa, SharedEdgesCoverEachSampleOnce) {
  const double cx = 31.37, cy = 30.81;  // the fan's centre, off the pixel grid
  std::vector<std::array<double, 2>> ring;
  for (int k = 0; k < 11; ++k) {
    const double a = 2 * M_PI * k / 11 + 0.3, radius = 20 + 7 * std::sin(3.0 * k);
    ring.push_back({std::round((cx + radius * std::cos(a)) * 256) / 256, std::round((cy + radius * std::sin(a)) * 256) / 256});
  }
  const std::array<double, 2> centre = {std::round(cx * 256) / 256, std::round(cy * 256) / 256};
  Scene s = test::camera_scene();
  for (std::size_t k = 0; k < ring.size(); ++k) {
    add_screen_triangle(s, {centre, ring[k], ring[(k + 1) % ring.size()]}, Color3(0.25f, 0.5f, 0.125f));
    s.materials.back().blend = BlendMode::add;
  }
  for (int samples : {4, 8, 16}) {
    for (auto [path, isa] : test::every_path()) {
      Canvas c(kSide, kSide, PixelFormat::rgba32f);
      Renderer r;
      ASSERT_TRUE(r.render(s, options_for(samples, path, isa), c.view()).ok());
      int inside = 0;
      for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
          // Pixels within 12 pixels of the centre lie inside the fan (its radius is at least 13).
          if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) > 12) continue;
          ++inside;
          ASSERT_EQ(c.channel_f(x, y, 0), 0.25f) << samples << " samples, " << to_string(path) << " " << to_string(isa)
                                                 << ", pixel " << x << ", " << y;
          ASSERT_EQ(c.channel_f(x, y, 2), 0.125f);
        }
      }
      ASSERT_GT(inside, 400);
    }
  }
}

// A triangle inside the top of one pixel, away from its centre: no pixel centre, so one sample
// draws nothing, while 4, 8 and 16 samples cover some of its samples (set-up, scalar and SIMD,
// does not drop it as too small to cover a pixel).
TEST(Msaa, TriangleBetweenPixelCentresCoversSamples) {
  Scene s = test::camera_scene();
  add_screen_triangle(s, {{{10.01, 10.01}, {10.7, 10.01}, {10.01, 10.45}}}, Color3(1, 1, 1));
  // 64 copies: the SIMD path sets up groups of triangles in lanes, and a lone one alone.
  auto& triangles = s.meshes.back().mesh.triangles;
  triangles.assign(64, triangles.front());
  for (int samples : {1, 4, 8, 16}) {
    for (auto [path, isa] : test::every_path()) {
      Canvas c(kSide, kSide, PixelFormat::rgba32f);
      FrameStats stats;
      ASSERT_TRUE(Renderer().render(s, options_for(samples, path, isa), c.view(), nullptr, &stats).ok());
      if (samples == 1) {
        EXPECT_EQ(c.channel_f(10, 10, 0), 0.0f);
        EXPECT_EQ(stats.triangles_drawn, 0u);
      } else {
        EXPECT_GT(c.channel_f(10, 10, 0), 0.0f) << samples << " " << to_string(path) << " " << to_string(isa);
        EXPECT_LT(c.channel_f(10, 10, 0), 0.5f);
      }
    }
  }
}

// Depth is tested per sample: where two quads cross in depth (along a diagonal of the image), the
// pixels along the line where they meet mix both colours (with depth at the pixel centre they
// would be one or the other).
TEST(Msaa, DepthIsTestedPerSample) {
  Scene s = test::camera_scene();
  test::add_quad(s, -0.8f, -0.8f, 0.8f, 0.8f, -2.0f, Color3(1, 0, 0));  // red, facing the camera
  test::add_quad(s, -0.8f, -0.8f, 0.8f, 0.8f, -2.0f, Color3(0, 0, 1));  // blue, turned about a diagonal
  Mat4 turn = Mat4::Identity();
  turn.topLeftCorner<3, 3>() = Eigen::AngleAxisf(0.5f, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  turn(2, 3) = -2.0f;
  s.meshes.back().mesh.positions = {Vec3(-0.8f, -0.8f, 0), Vec3(0.8f, -0.8f, 0), Vec3(0.8f, 0.8f, 0), Vec3(-0.8f, 0.8f, 0)};
  s.objects.back().model = turn;
  for (int samples : {1, 4, 16}) {
    for (auto [path, isa] : test::every_path()) {
      RenderOptions o = options_for(samples, path, isa);
      Canvas c(kSide, kSide, PixelFormat::rgba32f);
      ASSERT_TRUE(Renderer().render(s, o, c.view()).ok());
      int mixed = 0;
      for (int y = 24; y < 40; ++y)
        for (int x = 0; x < kSide; ++x) mixed += c.channel_f(x, y, 0) > 0.01f && c.channel_f(x, y, 2) > 0.01f;
      if (samples == 1) {
        EXPECT_EQ(mixed, 0);
      } else {
        EXPECT_GE(mixed, 12) << samples << " samples, " << to_string(path) << " " << to_string(isa);  // about a pixel a row
      }
    }
  }
}

// The scene of the tests below: overlapping lit, textured, blended and fogged objects.
Scene busy_scene() {
  Scene s = make_default_scene();
  s.fog.mode = FogMode::linear;
  s.fog.start = 2, s.fog.end = 30;
  for (Material& m : s.materials) m.shininess = std::min(m.shininess, 128.0f);
  s.materials.front().blend = BlendMode::alpha;
  s.materials.front().alpha = 0.7f;
  return s;
}

// Every path and ISA covers the same samples: the built-in scene drawn flat (one colour a
// triangle) and in Phong (the SIMD path gathers each pixel once with its samples, the scalar one
// runs per sample) is within a step on the reference, scalar and SIMD paths, with each count.
TEST(Msaa, EveryPathCoversTheSameSamples) {
  Scene s = make_default_scene();
  for (Material& m : s.materials) m.specular = Color3::Zero();  // flat colours that do not depend on the path's lighting
  for (int samples : {4, 8, 16})
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::phong}) {
    std::vector<std::uint8_t> first;
    for (auto [path, isa] : test::every_path()) {
      Canvas c(96, 64);
      RenderOptions o = options_for(samples, path, isa);
      o.shading = shading;
      o.cull = CullMode::back;
      o.clear_color = {0.1f, 0.2f, 0.3f, 1.0f};
      ASSERT_TRUE(Renderer().render(s, o, c.view()).ok());
      if (first.empty()) {
        first = c.pixels();
        continue;
      }
      // Lighting differs by rounding between paths (within a step); coverage differences would
      // show as whole colour changes.
      const auto got = c.pixels();
      int worst = 0;
      for (std::size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::abs(int(got[i]) - int(first[i])));
      EXPECT_LE(worst, 1) << samples << " samples, " << to_string(shading) << ", " << to_string(path) << " " << to_string(isa);
    }
  }
}

// Alpha to coverage: a white quad over the whole image, emissive, of alpha a, keeps in each pixel
// the samples s of N with a > s / N, so the resolved pixel is k / N white with k = ceil(a N); at
// one sample it does nothing (GL), and the alpha test still applies after it. Every path and ISA.
TEST(Msaa, AlphaToCoverageKeepsTheSamplesBelowTheAlpha) {
  for (auto [path, isa] : test::every_path())
  for (int samples : {1, 4, 8, 16})
  for (float cutoff : {0.0f, 0.5f})
  for (float alpha : {0.0f, 0.2f, 0.25f, 0.3f, 0.5f, 0.9f, 1.0f}) {
    Scene s = test::camera_scene();
    test::add_quad(s, -2, -2, 2, 2, -1, Color3(1, 1, 1));
    s.materials.back().alpha = alpha;
    s.materials.back().alpha_cutoff = cutoff;
    s.materials.back().alpha_to_coverage = true;
    Canvas c(kSide, kSide, PixelFormat::rgba32f);
    ASSERT_TRUE(Renderer().render(s, options_for(samples, path, isa), c.view()).ok());
    int k = 0;
    for (int i = 0; i < samples; ++i) k += samples == 1 || double(alpha) > double(i) / samples;
    if (alpha < cutoff) k = 0;
    const std::string what = std::to_string(samples) + " samples, alpha " + std::to_string(alpha) + ", cutoff " +
                             std::to_string(cutoff) + ", " + to_string(path) + " " + to_string(isa);
    for (int y : {0, 17, 63})
      for (int x : {0, 40, 63}) {
        ASSERT_FLOAT_EQ(c.channel_f(x, y, 0), float(k) / float(samples)) << what;
        ASSERT_FLOAT_EQ(c.channel_f(x, y, 3), alpha * float(k) / float(samples)) << what;
      }
  }
}

// Alpha to coverage with a texture's alpha (a ramp in 16 steps, each between two thresholds
// s / 16), over a red quad behind: every path and ISA covers the same samples in flat, Gouraud and
// Phong shading, within a step; the image holds every level from none to all of the samples.
TEST(Msaa, AlphaToCoverageIsTheSameOnEveryPath) {
  Scene s = test::camera_scene();
  test::add_quad(s, -2, -2, 2, 2, -2, Color3(1, 0, 0));
  test::add_quad(s, -1, -1, 1, 1, -1, Color3(0.2f, 0.9f, 0.5f));
  Mesh& m = s.meshes.back().mesh;
  m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  std::vector<std::uint8_t> ramp(16 * 4);
  for (int i = 0; i < 16; ++i) {
    ramp[4 * i + 0] = static_cast<std::uint8_t>(255 - 9 * i), ramp[4 * i + 1] = 200, ramp[4 * i + 2] = static_cast<std::uint8_t>(16 * i);
    ramp[4 * i + 3] = static_cast<std::uint8_t>(std::lround(255.0 * (i + 0.5) / 16));
  }
  TextureOptions to;
  to.filter = TextureFilter::nearest;
  s.textures.push_back(*make_texture("ramp", 16, 1, ramp, to));
  s.materials.back().diffuse_texture = 0;
  s.materials.back().texture_mode = TextureMode::modulate;
  s.materials.back().alpha_to_coverage = true;
  for (int samples : {4, 8, 16})
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    std::vector<std::uint8_t> first;
    for (auto [path, isa] : test::every_path()) {
      Canvas c(kSide, kSide);
      RenderOptions o = options_for(samples, path, isa);
      o.shading = shading;
      ASSERT_TRUE(Renderer().render(s, o, c.view()).ok());
      if (first.empty()) {
        first = c.pixels();
        std::vector<int> reds;  // the red behind, per column of the ramp's middle row
        for (int x = 0; x < kSide; ++x) reds.push_back(c.byte(x, kSide / 2, 0));
        std::sort(reds.begin(), reds.end());
        EXPECT_GE(std::unique(reds.begin(), reds.end()) - reds.begin(), samples == 16 ? 16 : samples) << samples;
        continue;
      }
      const auto got = c.pixels();
      int worst = 0;
      for (std::size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::abs(int(got[i]) - int(first[i])));
      EXPECT_LE(worst, 1) << samples << " samples, " << to_string(shading) << ", " << to_string(path) << " " << to_string(isa);
    }
  }
}

// The samples are averaged in linear colour, then encoded: an sRGB image is the linear float
// image's pixels encoded one by one.
TEST(Msaa, ResolvesInLinearColourBeforeEncoding) {
  const Scene s = busy_scene();
  for (int samples : {4, 16}) {
    RenderOptions o;
    o.samples = samples;
    Canvas linear(96, 64, PixelFormat::rgba32f), encoded(96, 64);
    ASSERT_TRUE(Renderer().render(s, o, linear.view()).ok());
    o.srgb = true;
    ASSERT_TRUE(Renderer().render(s, o, encoded.view()).ok());
    int edges = 0;
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 96; ++x) {
        for (int c = 0; c < 3; ++c) {
          const double v = std::clamp(double(linear.channel_f(x, y, c)), 0.0, 1.0);
          const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
          ASSERT_NEAR(encoded.byte(x, y, c), 255 * e, 0.5 + 1e-3) << x << ", " << y;
        }
        edges += linear.channel_f(x, y, 3) > 0 && linear.channel_f(x, y, 3) < 1;
      }
    }
    EXPECT_GT(edges, 0);
  }
}

// The same bytes for any thread count, with every sample count and shading mode.
TEST(Msaa, SameBytesForAnyThreadCount) {
  const Scene s = busy_scene();
  for (int samples : {4, 8, 16}) {
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      RenderOptions o;
      o.samples = samples;
      o.shading = shading;
      o.tile_size = 16;
      o.threads = 1;
      Canvas one(80, 56);
      ASSERT_TRUE(Renderer().render(s, o, one.view()).ok());
      for (int threads : {2, 3}) {
        o.threads = threads;
        Canvas c(80, 56);
        ASSERT_TRUE(Renderer().render(s, o, c.view()).ok());
        EXPECT_TRUE(c.pixels() == one.pixels()) << samples << " samples, " << to_string(shading) << ", " << threads << " threads";
      }
    }
  }
}

// More samples smooth the edges: the 4-sample image has pixels between the 1-sample image's
// colours along silhouettes, and the interiors are unchanged (shading per pixel, at its centre).
TEST(Msaa, EdgesBlendAndInteriorsStay) {
  const Scene s = make_default_scene();
  RenderOptions o;
  Canvas one(96, 64), four(96, 64);
  ASSERT_TRUE(Renderer().render(s, o, one.view()).ok());
  o.samples = 4;
  ASSERT_TRUE(Renderer().render(s, o, four.view()).ok());
  int same = 0, different = 0;
  for (int y = 1; y < 63; ++y) {
    for (int x = 1; x < 95; ++x) {
      // A pixel whose 3x3 neighbourhood is one colour in the 1-sample image lies inside a surface.
      bool flat = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          for (int c = 0; c < 3; ++c) flat &= std::abs(one.byte(x + dx, y + dy, c) - one.byte(x, y, c)) <= 8;
      bool equal = true;
      for (int c = 0; c < 4; ++c) equal &= one.byte(x, y, c) == four.byte(x, y, c);
      if (flat) {
        same += equal;
      } else {
        different += !equal;
      }
    }
  }
  std::printf("interior pixels unchanged: %d; edge pixels changed: %d\n", same, different);
  EXPECT_GT(different, 50);
  EXPECT_GT(same, 1000);
}

// The depth view holds each pixel's nearest sample: a pixel that any sample of a triangle covers
// has less than far depth.
TEST(Msaa, DepthViewHoldsTheNearestSample) {
  Scene s = test::camera_scene();
  add_screen_triangle(s, {{{10.3, 8.6}, {50.2, 20.1}, {17.9, 55.4}}}, Color3(1, 1, 1));
  RenderOptions o = options_for(16);
  Canvas c(kSide, kSide, PixelFormat::rgba32f);
  std::vector<float> depth(kSide * kSide);
  const DepthView dv{depth.data(), kSide, kSide, kSide * sizeof(float), false};
  ASSERT_TRUE(Renderer().render(s, o, c.view(), &dv).ok());
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) EXPECT_EQ(c.channel_f(x, y, 0) > 0, depth[y * kSide + x] < 1.0f) << x << ", " << y;
}

// Sample counts other than 1, 4, 8 and 16 are refused, naming the option; the tile memory grows
// with the count in the frame's memory estimate.
TEST(Msaa, OtherCountsAreRefusedAndMemoryGrows) {
  const Scene s = make_default_scene();
  for (int bad : {0, 2, 3, 5, 32, -4}) {
    RenderOptions o;
    o.samples = bad;
    Canvas c(16, 16);
    const Status st = Renderer().render(s, o, c.view());
    EXPECT_EQ(st.code(), ErrorCode::invalid_argument) << bad;
    EXPECT_NE(st.message().find("options.samples"), std::string::npos) << st.message();
    EXPECT_TRUE(c.untouched());
  }
  RenderOptions one, sixteen;
  sixteen.samples = 16;
  EXPECT_GT(estimate_frame_bytes(s, sixteen, 1920, 1080), estimate_frame_bytes(s, one, 1920, 1080) + 15 * 5 * 64 * 64 * 4);
}

}  // namespace
}  // namespace facet
