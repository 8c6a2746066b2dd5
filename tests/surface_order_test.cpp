// Surfaces, continued from surface_test.cpp: sRGB output, a mesh's material groups, stability at
// extreme texture coordinates, and the order of transparent objects.
#include <bit>
#include <cmath>
#include <cstring>

#include "io/srgb.hpp"
#include "texture/sampler.hpp"
#include "render_support.hpp"
#include "surface_support.hpp"

namespace facet {
namespace {

// sRGB output: every float of [0, 1] at a fine spacing, and the floats around every threshold,
// encode to the correctly rounded 8-bit value of the exact transfer function.
double srgb_encode(double x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055; }

TEST(Srgb, EncodingIsCorrectlyRounded) {
  SrgbTable t;
  make_srgb_table(t);
  auto exact = [](float x) {
    return static_cast<int>(std::floor(std::clamp(srgb_encode(std::clamp<double>(x, 0, 1)), 0.0, 1.0) * 255.0 + 0.5));
  };
  int checked = 0;
  for (int i = 0; i <= 1 << 20; ++i) {
    const float x = static_cast<float>(i) / float(1 << 20);
    ASSERT_EQ(srgb_unorm8_search(t.threshold, x), exact(x)) << x;
    ASSERT_EQ(srgb_unorm8(t, x), exact(x)) << x;
    ++checked;
  }
  for (int k = 1; k < 256; ++k) {  // both sides of each threshold
    const float at = t.threshold[k], below = std::nextafter(at, -1.0f);
    EXPECT_EQ(srgb_unorm8_search(t.threshold, at), k);
    EXPECT_EQ(srgb_unorm8(t, at), k);
    EXPECT_EQ(srgb_unorm8_search(t.threshold, below), k - 1);
    EXPECT_EQ(srgb_unorm8(t, below), k - 1);
    EXPECT_EQ(exact(at), k);
    EXPECT_EQ(exact(below), k - 1);
  }
  EXPECT_EQ(srgb_unorm8(t, std::nanf("")), 0);
  EXPECT_EQ(srgb_unorm8(t, -1.0f), 0);
  EXPECT_EQ(srgb_unorm8(t, 7.0f), 255);
  EXPECT_GT(checked, 1000000);
}

// The SIMD resolve's buckets (io/srgb.hpp): each float in [2^-13, 1) has its bucket's base plus one
// if it reaches the one threshold the bucket may hold; no bucket holds two, and the buckets cover
// every threshold.
TEST(Srgb, EveryBucketHoldsAtMostOneThreshold) {
  SrgbTable t;
  make_srgb_table(t);
  EXPECT_GT(t.threshold[1], 0x1p-13f);
  EXPECT_LT(t.threshold[255], 1.0f);
  int inside_total = 0;
  for (int b = 0; b < SrgbTable::kBuckets; ++b) {
    const float lo = std::bit_cast<float>((b + SrgbTable::kBucketBias) << SrgbTable::kBucketShift);
    const float hi = std::bit_cast<float>((b + 1 + SrgbTable::kBucketBias) << SrgbTable::kBucketShift);
    int below = 0, inside = 0;
    for (int k = 1; k < 256; ++k) {
      below += t.threshold[k] <= lo;
      inside += t.threshold[k] > lo && t.threshold[k] < hi;
    }
    ASSERT_LE(inside, 1) << "bucket " << b;
    const std::int32_t base = t.bucket[b] >> SrgbTable::kBaseShift, low = t.bucket[b] & SrgbTable::kLowMask;
    EXPECT_EQ(base, below) << "bucket " << b;
    EXPECT_EQ(low != 0x10000, inside == 1) << "bucket " << b;
    EXPECT_LE(low, 0x10000) << "bucket " << b;
    EXPECT_EQ(srgb_unorm8_search(t.threshold, lo), base);
    inside_total += inside;
  }
  EXPECT_EQ(std::bit_cast<float>((SrgbTable::kBuckets + SrgbTable::kBucketBias) << SrgbTable::kBucketShift), 1.0f);
  EXPECT_GT(inside_total, 200);  // most thresholds are not a bucket's first float
  // The scalar bucket encoder against the search on floats spread over every exponent up to 1.
  std::uint64_t checked = 0;
  for (std::uint32_t bits = 0; bits <= 0x3F800100u; bits += 97) {
    const float v = std::bit_cast<float>(bits);
    ASSERT_EQ(srgb_unorm8(t, v), srgb_unorm8_search(t.threshold, v)) << v;
    ++checked;
  }
  EXPECT_GT(checked, 10000000u);
}

// Rendering with srgb: colour encoded, alpha linear, clear colour encoded, every path and format.
TEST(Srgb, RenderEncodesColourNotAlpha) {
  Scene s = test::camera_scene();
  const Color3 e(0.02f, 0.2f, 0.7f);
  test::add_quad(s, -1, -1, 1, 1, -3, e);
  s.materials.back().alpha = 0.3f;
  for (auto [path, isa] : every_path()) {
    for (PixelFormat format : {PixelFormat::rgba8, PixelFormat::bgra8}) {
      Canvas c(32, 32, format);
      RenderOptions o = test::gl_options();
      o.path = path;
      o.isa = isa;
      o.srgb = true;
      o.clear_color = {0.5f, 0.001f, 0.0f, 0.25f};
      Renderer r;
      ASSERT_TRUE(r.render(s, o, c.view()).ok());
      const int red = format == PixelFormat::rgba8 ? 0 : 2, blue = 2 - red;
      auto enc = [](double v) { return static_cast<int>(std::floor(srgb_encode(v) * 255.0 + 0.5)); };
      SCOPED_TRACE(std::string(to_string(path)) + " " + to_string(isa));
      EXPECT_EQ(c.byte(16, 16, red), enc(e.x()));
      EXPECT_EQ(c.byte(16, 16, 1), enc(e.y()));
      EXPECT_EQ(c.byte(16, 16, blue), enc(e.z()));
      EXPECT_EQ(c.byte(16, 16, 3), 77);  // 0.3 * 255 + 0.5, linear
      EXPECT_EQ(c.byte(0, 0, red), enc(0.5));
      EXPECT_EQ(c.byte(0, 0, 1), enc(0.001));
      EXPECT_EQ(c.byte(0, 0, 3), 64);
    }
  }
}

// Per-face materials: each material group of a mesh draws with the scene material of its name.
TEST(Surfaces, MeshMaterialGroupsDrawWithTheirOwnMaterials) {
  Scene s = test::camera_scene();
  test::add_quad(s, -5, -5, 5, 5, -3, Color3(1, 0, 0));  // triangles (0, 1, 2) lower right, (0, 2, 3) upper left
  s.materials.back().name = "red";
  Material green = s.materials.back();
  green.name = "green";
  green.emissive = Color3(0, 1, 0);
  s.materials.push_back(green);
  s.meshes.back().mesh.groups = {{"red", 0, 1}, {"green", 1, 1}};
  s.objects.back().mesh_materials = true;
  ASSERT_TRUE(validate_scene(s).ok()) << validate_scene(s).message();
  for (auto [path, isa] : every_path()) {
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      SCOPED_TRACE(std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading));
      Canvas c(32, 32);
      RenderOptions o = test::gl_options();
      o.path = path, o.isa = isa, o.shading = shading;
      Renderer r;
      ASSERT_TRUE(r.render(s, o, c.view()).ok());
      EXPECT_EQ(c.byte(24, 24, 0), 255);  // lower right: red
      EXPECT_EQ(c.byte(24, 24, 1), 0);
      EXPECT_EQ(c.byte(8, 8, 0), 0);  // upper left: green
      EXPECT_EQ(c.byte(8, 8, 1), 255);
    }
  }
  Scene bad = s;
  bad.meshes.back().mesh.groups[1].material = "blue";
  EXPECT_EQ(validate_scene(bad).field(), "objects[0].mesh_materials");
  EXPECT_NE(validate_scene(bad).message().find("'blue'"), std::string::npos) << validate_scene(bad).message();
  bad = s;
  bad.meshes.back().mesh.groups.clear();
  EXPECT_EQ(validate_scene(bad).field(), "objects[0].mesh_materials");
}

// A mesh split into groups that all name its own material draws the same bytes as the whole mesh
// (each group transforms and lights only the vertices its triangles use).
TEST(Surfaces, GroupsOfOneMaterialDrawLikeTheWholeMesh) {
  Scene whole = make_default_scene();
  Scene split = whole;
  for (std::size_t o = 0; o < split.objects.size(); ++o) {
    Instance& inst = split.objects[o];
    Mesh& mesh = split.meshes[inst.mesh].mesh;
    if (!mesh.groups.empty()) continue;  // a mesh shared by several objects is split once
    const auto t = static_cast<std::uint32_t>(mesh.triangle_count());
    const std::string name = split.materials[inst.material].name;
    mesh.groups = {{name, 0, t / 3}, {name, t / 3, t / 3}, {name, 2 * (t / 3), t - 2 * (t / 3)}};
  }
  for (std::size_t o = 0; o < split.objects.size(); ++o) {
    Instance& inst = split.objects[o];
    // Only objects whose mesh's groups name their own material (the first object of each mesh).
    inst.mesh_materials = split.meshes[inst.mesh].mesh.groups[0].material == split.materials[inst.material].name;
  }
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
      RenderOptions o = test::gl_options();
      o.shading = shading, o.path = path, o.threads = 2;
      EXPECT_TRUE(render_pixels(whole, o) == render_pixels(split, o)) << to_string(shading) << " " << to_string(path);
    }
  }
}

// Stability: texture coordinates of 1e7 (float spacing 1 there: the texture's corner, documented),
// derivatives of zero (every corner the same uv) and of infinity (a textured quad seen edge-on), a
// fully transparent blended object: finite output, and the transparent object changes nothing.
TEST(Surfaces, StableAtHugeUvsZeroAndInfiniteDerivatives) {
  Scene s = test::camera_scene();
  s.textures.push_back(texture_from(16, 16, TextureFilter::trilinear, [](int i, int j) {
    return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(16 * i), static_cast<std::uint8_t>(16 * j), 99, 255};
  }));
  test::add_quad(s, -5, -5, 0, 5, -3, Color3(1, 1, 1));  // left half: uvs of 1e7
  s.meshes.back().mesh.uvs = {Vec2(1e7f, -1e7f), Vec2(1e7f + 1, -1e7f), Vec2(1e7f + 1, -1e7f + 1), Vec2(1e7f, -1e7f + 1)};
  s.materials.back().diffuse_texture = 0;
  test::add_quad(s, 0, -5, 5, 5, -3, Color3(1, 1, 1));  // right half: one uv everywhere
  s.meshes.back().mesh.uvs.assign(4, Vec2(0.53f, 0.47f));
  s.materials.back().diffuse_texture = 0;
  test::add_quad(s, -1, -1, 1, 1, -2, Color3(1, 1, 1));  // edge-on: rotated to contain the view ray
  add_uvs(s);
  s.materials.back().diffuse_texture = 0;
  Mat4 edge = Mat4::Identity();
  edge.topLeftCorner<3, 3>() = Eigen::AngleAxisf(1.5707963f, Vec3::UnitY()).toRotationMatrix();
  edge(2, 3) = -2.5f;
  s.objects.back().model = edge;
  s.objects.back().material = static_cast<std::uint32_t>(s.materials.size() - 1);
  Scene with_ghost = s;
  test::add_quad(with_ghost, -5, -5, 5, 5, -2, Color3(1, 0, 1));  // in front of everything, invisible
  with_ghost.materials.back().blend = BlendMode::alpha;
  with_ghost.materials.back().alpha = 0.0f;
  for (auto [path, isa] : every_path()) {
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong})
    for (PixelPrecision precision : {PixelPrecision::exact, PixelPrecision::fast}) {
      SCOPED_TRACE(std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading) + " " +
                   to_string(precision));
      RenderOptions o = test::gl_options();
      o.path = path, o.isa = isa, o.shading = shading, o.pixel_precision = precision;
      Canvas f(64, 64, PixelFormat::rgba32f);
      Renderer r;
      ASSERT_TRUE(r.render(s, o, f.view()).ok());
      for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
          for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(f.channel_f(x, y, c))) << x << " " << y;
      // One uv everywhere: exactly the texel there at level 0 (bilinear between texel centres);
      // the 16-bit tier within its bilinear contract (1.5 steps).
      const auto want = texture::sample_reference(texture::make_sampler(s.textures[0]), 0.53, 0.47, -1.0);
      const double tolerance = precision == PixelPrecision::fast ? 1.5 / 255.0 : 1e-5;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f.channel_f(56, 32, c), want[static_cast<std::size_t>(c)], tolerance);
      EXPECT_TRUE(render_pixels(s, o, 64, 64) == render_pixels(with_ghost, o, 64, 64));
    }
  }
}

// TransparentOrder::back_to_front: a scene whose blended quads are submitted near to far, with an
// opaque quad among them and the opaque background last, looked at along +x (so that the order
// comes from eye-space depth, not world z). `hand` is the same scene in the order the rule names,
// drawn in submission order: opaque objects in scene order, then blended ones far to near.
struct OrderScenes {
  Scene sorted, hand;
};
OrderScenes order_scenes() {
  Scene s = test::camera_scene();
  s.camera.target = Vec3(1, 0, 0);
  // Quads built facing +z at depth -d, then turned to face -x at distance d along +x.
  auto quad = [&](float d, float x0, float y0, float x1, float y1, const Color3& c, float alpha) {
    test::add_quad(s, x0, y0, x1, y1, -d, c);
    Mat4 turn = Mat4::Identity();
    turn.topLeftCorner<3, 3>() = Eigen::AngleAxisf(-1.5707963f, Vec3::UnitY()).toRotationMatrix();
    s.objects.back().model = turn;
    if (alpha < 1.0f) {
      s.materials.back().blend = BlendMode::alpha;
      s.materials.back().alpha = alpha;
    }
  };
  quad(3.0f, -2.0f, -2.0f, 1.0f, 1.0f, Color3(1, 0, 0), 0.5f);    // 0: near, blended
  quad(4.0f, -1.0f, -1.0f, 2.5f, 2.5f, Color3(0, 1, 0), 0.5f);    // 1: middle, blended
  quad(3.5f, 0.5f, -3.0f, 3.0f, 0.0f, Color3(1, 1, 0), 1.0f);     // 2: opaque, between them
  quad(5.0f, -3.0f, -1.5f, 0.5f, 3.0f, Color3(0, 0, 1), 0.5f);    // 3: far, blended
  quad(8.0f, -9.0f, -9.0f, 9.0f, 9.0f, Color3(0.5f, 0.5f, 0.5f), 1.0f);  // 4: background, opaque
  OrderScenes out{s, s};
  out.sorted.transparent_order = TransparentOrder::back_to_front;
  out.hand.objects = {s.objects[2], s.objects[4], s.objects[3], s.objects[1], s.objects[0]};
  return out;
}

TEST(TransparentOrder, BackToFrontDrawsWhatTheSceneSortedByHandDraws) {
  const OrderScenes o = order_scenes();
  ASSERT_TRUE(validate_scene(o.sorted).ok()) << validate_scene(o.sorted).message();
  EXPECT_EQ(draw_order(o.sorted), (std::vector<std::size_t>{2, 4, 3, 1, 0}));
  Scene submitted = o.sorted;
  submitted.transparent_order = TransparentOrder::submission;
  EXPECT_EQ(draw_order(submitted), (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  for (auto [path, isa] : every_path()) {
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      SCOPED_TRACE(std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading));
      RenderOptions opt = test::gl_options();
      opt.path = path, opt.isa = isa, opt.shading = shading;
      const auto sorted = render_pixels(o.sorted, opt, 96, 96);
      EXPECT_TRUE(sorted == render_pixels(o.hand, opt, 96, 96));
      EXPECT_FALSE(sorted == render_pixels(submitted, opt, 96, 96));  // the order matters in this scene
    }
  }
}

// Equal depths keep scene order; an object is transparent when any of its group materials blends;
// a scene without blended objects draws in scene order.
TEST(TransparentOrder, TiesKeepSceneOrderAndGroupsCount) {
  Scene s = test::camera_scene();
  s.transparent_order = TransparentOrder::back_to_front;
  for (int k = 0; k < 3; ++k) {
    const float x = static_cast<float>(k);
    test::add_quad(s, x - 2.0f, -2.0f, x + 1.0f, 1.0f, -4.0f, Color3(k == 0, k == 1, k == 2));
    s.materials.back().blend = BlendMode::alpha;
    s.materials.back().alpha = 0.5f;
  }
  EXPECT_EQ(draw_order(s), (std::vector<std::size_t>{0, 1, 2}));
  // A two-group quad behind them, first group opaque, second blended, submitted last: transparent,
  // and the farthest, so drawn first; with both groups opaque it is drawn first as an opaque object.
  test::add_quad(s, -5, -5, 5, 5, -6, Color3(1, 1, 1));
  s.materials.back().name = "white";
  Material glass = s.materials.back();
  glass.name = "glass";
  glass.blend = BlendMode::premultiplied;
  s.materials.push_back(glass);
  s.meshes.back().mesh.groups = {{"white", 0, 1}, {"glass", 1, 1}};
  s.objects.back().mesh_materials = true;
  ASSERT_TRUE(validate_scene(s).ok()) << validate_scene(s).message();
  EXPECT_TRUE(is_transparent(s, s.objects.back()));
  EXPECT_EQ(draw_order(s), (std::vector<std::size_t>{3, 0, 1, 2}));
  // Out-of-range indices (an unvalidated scene) are not transparent and crash nothing.
  Scene bad = s;
  bad.objects[0].material = 99;
  bad.objects[1].mesh = 99;
  bad.objects[1].mesh_materials = true;
  // 0: its material is missing, so opaque; 1: its own (blended) material, no mesh: depth 0, last.
  EXPECT_EQ(draw_order(bad), (std::vector<std::size_t>{0, 3, 2, 1}));
  s.meshes.back().mesh.groups = {{"white", 0, 2}};
  EXPECT_FALSE(is_transparent(s, s.objects.back()));
  EXPECT_EQ(draw_order(s), (std::vector<std::size_t>{3, 0, 1, 2}));  // opaque first
  for (Material& m : s.materials) m.blend = BlendMode::opaque;
  EXPECT_EQ(draw_order(s), (std::vector<std::size_t>{0, 1, 2, 3}));
}

TEST(TransparentOrder, BackToFrontSameBytesForAnyThreadCount) {
  Scene s = surfaces_scene();
  s.transparent_order = TransparentOrder::back_to_front;
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
      RenderOptions o = test::gl_options();
      o.shading = shading, o.path = path, o.tile_size = 32, o.threads = 1;
      const auto one = render_pixels(s, o);
      for (int threads : {2, 8}) {
        o.threads = threads;
        EXPECT_TRUE(render_pixels(s, o) == one) << to_string(shading) << " " << to_string(path) << " threads " << threads;
      }
    }
  }
  const OrderScenes o = order_scenes();
  RenderOptions opt = test::gl_options();
  opt.tile_size = 16, opt.threads = 1;
  const auto one = render_pixels(o.sorted, opt, 96, 96);
  for (int threads : {2, 3, 8}) {
    opt.threads = threads;
    EXPECT_TRUE(render_pixels(o.sorted, opt, 96, 96) == one) << threads;
  }
}

}  // namespace
}  // namespace facet
