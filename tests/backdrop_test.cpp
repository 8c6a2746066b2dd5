// The surroundings drawn behind the model (Scene::background == environment, tile/backdrop.hpp):
// each pixel sees the picture along its ray (orientation and rotation as the lighting reads the
// picture), times the intensity; surfaces cover it, blended surfaces blend over it and
// multisampled edges resolve against it; the same bytes on every path and thread count; the
// display transform exposes it; a background without surroundings is refused by name.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "facet/facet.hpp"
#include "render_support.hpp"

namespace facet {
namespace {

// 64 x 32, read as three.js reads a picture (facet/environment_light.hpp): the middle half of the
// columns is the +X hemisphere (red), the rest -X (blue); the upper half of the rows (above the
// horizon) has green 1.
EnvironmentLight backdrop_halves() {
  EnvironmentLight e;
  e.source = EnvironmentSource::image;
  e.width = 64, e.height = 32;
  e.rgb.resize(64 * 32 * 3);
  for (int r = 0; r < 32; ++r) {
    for (int c = 0; c < 64; ++c) {
      float* t = &e.rgb[3 * (std::size_t(r) * 64 + std::size_t(c))];
      const bool plus_x = c >= 16 && c < 48;
      t[0] = plus_x ? 1.0f : 0.0f, t[1] = r < 16 ? 1.0f : 0.0f, t[2] = plus_x ? 0.0f : 1.0f;
    }
  }
  return e;
}

// The camera at the origin looking along -Z (90 degrees), nothing in view but what the test adds.
Scene backdrop_test_scene() {
  Scene s = test::camera_scene();
  s.environment_light = backdrop_halves();
  s.background = Background::environment;
  return s;
}

std::vector<float> backdrop_floats(const Scene& s, RenderOptions o, int w, int h) {
  std::vector<float> out(4 * std::size_t(w) * std::size_t(h), -1.0f);
  Renderer r;
  o.hdr = true;
  o.clear_color = {0.25f, 0.5f, 0.75f, 0.0f};
  const ImageView v{out.data(), w, h, std::size_t(w) * 16, PixelFormat::rgba32f, false};
  const Status st = r.render(s, o, v, nullptr, nullptr);
  EXPECT_TRUE(st.ok()) << st.message();
  return out;
}

const float* pixel_at(const std::vector<float>& px, int w, int x, int y) { return &px[4 * (std::size_t(y) * std::size_t(w) + std::size_t(x))]; }

TEST(Backdrop, EachPixelSeesThePictureAlongItsRay) {
  Scene s = backdrop_test_scene();
  s.environment_light.intensity = 2.0f;
  for (const auto& [path, isa] : test::every_path()) {
    RenderOptions o;
    o.path = path, o.isa = isa;
    const int w = 64, h = 48;
    const std::vector<float> px = backdrop_floats(s, o, w, h);
    const std::string what = std::string(to_string(path)) + " " + to_string(isa);
    // Looking along -Z: the right edge sees towards +X (red), the left towards -X (blue); the top
    // rows look above the horizon (green), the bottom rows below it.
    const float* right_top = pixel_at(px, w, w - 2, 2);
    const float* left_bottom = pixel_at(px, w, 1, h - 2);
    EXPECT_FLOAT_EQ(right_top[0], 2.0f) << what;
    EXPECT_FLOAT_EQ(right_top[1], 2.0f) << what;
    EXPECT_FLOAT_EQ(right_top[2], 0.0f) << what;
    EXPECT_FLOAT_EQ(left_bottom[0], 0.0f) << what;
    EXPECT_FLOAT_EQ(left_bottom[1], 0.0f) << what;
    EXPECT_FLOAT_EQ(left_bottom[2], 2.0f) << what;
    for (std::size_t i = 3; i < px.size(); i += 4) ASSERT_EQ(px[i], 1.0f) << what << ": the backdrop is opaque";
  }
  // Turned by half a turn about +Y: the sides swap.
  s.environment_light.rotation_deg = 180.0f;
  const std::vector<float> turned = backdrop_floats(s, {}, 64, 48);
  EXPECT_FLOAT_EQ(pixel_at(turned, 64, 62, 2)[2], 2.0f);
  EXPECT_FLOAT_EQ(pixel_at(turned, 64, 1, 46)[0], 2.0f);
  // The default background is the clear colour.
  s.background = Background::colour;
  const std::vector<float> plain = backdrop_floats(s, {}, 64, 48);
  EXPECT_EQ(pixel_at(plain, 64, 62, 2)[0], 0.25f);
  EXPECT_EQ(pixel_at(plain, 64, 62, 2)[3], 0.0f);
}

TEST(Backdrop, SurfacesCoverItBlendOverItAndEdgesResolveAgainstIt) {
  Scene s = backdrop_test_scene();
  // An opaque black quad on the left half of the view, a half-transparent white one on the right.
  test::add_quad(s, -2.0f, -1.0f, -0.05f, 1.0f, -2.0f, Color3(0.0f, 0.0f, 0.0f));
  test::add_quad(s, 0.05f, -1.0f, 2.0f, 1.0f, -2.0f, Color3(1.0f, 1.0f, 1.0f));
  Material& glass = s.materials.back();
  glass.blend = BlendMode::alpha;
  glass.alpha = 0.5f;
  const int w = 64, h = 48;
  for (const auto& [path, isa] : test::every_path()) {
    RenderOptions o;
    o.path = path, o.isa = isa;
    const std::string what = std::string(to_string(path)) + " " + to_string(isa);
    const std::vector<float> px = backdrop_floats(s, o, w, h);
    const float* black = pixel_at(px, w, 16, 24);
    EXPECT_EQ(black[0], 0.0f) << what;
    EXPECT_EQ(black[2], 0.0f) << what;
    EXPECT_EQ(black[3], 1.0f) << what;
    // White at half alpha over the red +X backdrop below the horizon (1, 0, 0): (1, 0.5, 0.5).
    const float* glassy = pixel_at(px, w, 48, 30);
    EXPECT_FLOAT_EQ(glassy[0], 1.0f) << what;
    EXPECT_FLOAT_EQ(glassy[1], 0.5f) << what;
    EXPECT_FLOAT_EQ(glassy[2], 0.5f) << what;
    // Between the quads, in a tile both touch: the backdrop below the horizon (no green), looking
    // straight ahead, where the picture turns from -X (blue) to +X (red).
    const float* gap = pixel_at(px, w, 32, 46);
    EXPECT_EQ(gap[1], 0.0f) << what;
    EXPECT_EQ(gap[0] + gap[2], 1.0f) << what;
    // Multisampled: an edge pixel of the black quad is part black, part backdrop, never the clear colour.
    o.samples = 4;
    const std::vector<float> ms = backdrop_floats(s, o, w, h);
    bool partial = false;
    for (int x = 0; x < w; ++x) {
      const float* p = pixel_at(ms, w, x, 30);  // below the horizon: the backdrop has no green
      EXPECT_NE(p[0], 0.25f) << what << " " << x;
      if (p[2] > 0.0f && p[2] < 1.0f && x < w / 2) partial = true;  // blue backdrop partly covered
    }
    EXPECT_TRUE(partial) << what << ": no edge pixel between the black quad and the blue backdrop";
  }
}

TEST(Backdrop, SameBytesForAnyThreadCountAndExposedByTheDisplay) {
  Scene s = backdrop_test_scene();
  s.meshes.push_back({"ball", make_uv_sphere(0.5f, 24, 12)});
  Material m;
  m.model = MaterialModel::pbr;
  m.metallic = 1.0f;
  m.roughness = 0.3f;
  s.materials.push_back(m);
  Instance inst{std::uint32_t(s.meshes.size() - 1), std::uint32_t(s.materials.size() - 1), Mat4::Identity()};
  inst.model(2, 3) = -2.0f;
  s.objects.push_back(inst);
  s.display.tone_mapping = ToneMapping::neutral;
  s.display.ev = -1.0f;
  std::vector<std::uint8_t> first;
  for (int samples : {1, 4}) {
    for (int threads : {1, 2, 3}) {
      test::Canvas img(96, 64);
      RenderOptions o;
      o.threads = threads, o.samples = samples;
      Renderer r;
      ASSERT_TRUE(r.render(s, o, img.view(), nullptr, nullptr).ok());
      if (threads == 1) first = img.pixels();
      EXPECT_EQ(img.pixels(), first) << threads << " threads, " << samples << " samples";
    }
  }
  // The top-left pixel sees (0, 1, 1) (-X, above the horizon): exposed and tone-mapped, so a stop
  // less is darker; red stays 0.
  auto top_left = [&](float ev) {
    s.display.ev = ev;
    test::Canvas img(96, 64);
    RenderOptions o;
    o.srgb = false;
    Renderer r;
    EXPECT_TRUE(r.render(s, o, img.view(), nullptr, nullptr).ok());
    return std::array<int, 3>{img.byte(0, 0, 0), img.byte(0, 0, 1), img.byte(0, 0, 2)};
  };
  const std::array<int, 3> dim = top_left(-1.0f), bright = top_left(0.0f);
  EXPECT_EQ(dim[0], 0);
  EXPECT_LT(dim[1], bright[1]);
  EXPECT_GT(dim[1], 60);
  EXPECT_LT(bright[1], 255);
}

// Flat and Gouraud frames with shadows are sums of sub-frames: the backdrop is in the base alone.
TEST(Backdrop, ShadowedFlatAndGouraudFramesDrawItOnce) {
  Scene s = backdrop_test_scene();
  test::add_quad(s, -0.5f, -0.5f, 0.5f, 0.5f, -2.0f, Color3(0.2f, 0.2f, 0.2f));
  Light sun;
  sun.shadow.method = ShadowMethod::raycast;
  s.lights.push_back(sun);
  for (ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    RenderOptions o;
    o.shading = shading;
    const std::vector<float> px = backdrop_floats(s, o, 64, 48);
    EXPECT_FLOAT_EQ(pixel_at(px, 64, 62, 2)[0], 1.0f) << to_string(shading);
    EXPECT_FLOAT_EQ(pixel_at(px, 64, 62, 2)[1], 1.0f) << to_string(shading);
  }
}

TEST(Backdrop, WithoutSurroundingsIsRefusedByName) {
  Scene s = test::camera_scene();
  s.background = Background::environment;
  Renderer r;
  std::vector<float> out(4 * 16 * 16);
  const ImageView v{out.data(), 16, 16, 16 * 16, PixelFormat::rgba32f, false};
  const Status st = r.render(s, {}, v, nullptr, nullptr);
  EXPECT_EQ(st.code(), ErrorCode::invalid_argument);
  EXPECT_EQ(st.field(), "background");
}

}  // namespace
}  // namespace facet
