// Exposure, tone mapping and the output's encoding (facet/display.hpp, docs/color.md): the
// operators against their published formulas in double, exposure's doubling, the meter, the
// background, sRGB output by default and colour textures of OBJ/MTL read as sRGB.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "io/image_convert.hpp"
#include "io/srgb.hpp"
#include "render_support.hpp"

namespace facet {
namespace {

// Khronos PBR Neutral in double, from its specification.
std::array<double, 3> neutral_reference(std::array<double, 3> c) {
  const double start = 0.8 - 0.04, desaturation = 0.15;
  const double x = std::min({c[0], c[1], c[2]});
  const double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
  for (double& v : c) v -= offset;
  const double peak = std::max({c[0], c[1], c[2]});
  if (peak < start) return c;
  const double d = 1.0 - start;
  const double new_peak = 1.0 - d * d / (peak + d - start);
  for (double& v : c) v *= new_peak / peak;
  const double g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
  for (double& v : c) v = v * (1.0 - g) + new_peak * g;
  return c;
}

double aces_reference(double x) { return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14); }

double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }

TEST(ToneMapping, OperatorsMatchTheirPublishedFormulasInDouble) {
  double worst_neutral = 0.0, worst_aces = 0.0;
  const double values[] = {0.0, 1e-4, 0.01, 0.05, 0.079, 0.08, 0.081, 0.18, 0.5, 0.75, 0.76, 0.77, 0.9, 1.0, 1.5, 3.0, 10.0, 100.0, 1e4};
  for (double r : values) {
    for (double g : values) {
      for (double b : values) {
        const std::array<float, 3> in{float(r), float(g), float(b)};
        const std::array<double, 3> exact_in{double(in[0]), double(in[1]), double(in[2])};
        const std::array<double, 3> n = neutral_reference(exact_in);
        const std::array<float, 3> fn = tone_map(ToneMapping::neutral, in);
        const std::array<float, 3> fa = tone_map(ToneMapping::aces, in);
        const std::array<float, 3> fc = tone_map(ToneMapping::none, in);
        for (int c = 0; c < 3; ++c) {
          worst_neutral = std::max(worst_neutral, std::abs(double(fn[c]) - clamp01(n[c])));
          worst_aces = std::max(worst_aces, std::abs(double(fa[c]) - clamp01(aces_reference(exact_in[c]))));
          EXPECT_EQ(fc[c], float(clamp01(exact_in[c])));
        }
      }
    }
  }
  // Float against double: a few units in the last place of values in [0, 1].
  EXPECT_LT(worst_neutral, 2e-6);
  EXPECT_LT(worst_aces, 2e-6);
  // The curves' landmarks: neutral keeps values below its shoulder (minus the small offset) and
  // never reaches white; ACES's fit maps 1 to about 0.80.
  EXPECT_NEAR(tone_map(ToneMapping::neutral, {0.5f, 0.5f, 0.5f})[0], 0.46f, 1e-6f);
  EXPECT_LT(tone_map(ToneMapping::neutral, {1e4f, 1e4f, 1e4f})[0], 1.0f);
  EXPECT_NEAR(tone_map(ToneMapping::aces, {1.0f, 1.0f, 1.0f})[0], 2.54 / 3.16, 1e-6);
  // Non-finite and negative light is black, not NaN.
  EXPECT_EQ(tone_map(ToneMapping::neutral, {std::nanf(""), -1.0f, 0.0f})[0], 0.0f);
}

TEST(ToneMapping, MeteredExposureMapsTheLogAverageToMiddleGrey) {
  EXPECT_FLOAT_EQ(metered_ev(0.18), 0.0f);
  EXPECT_FLOAT_EQ(metered_ev(0.36), -1.0f);
  EXPECT_FLOAT_EQ(metered_ev(0.045), 2.0f);
  EXPECT_EQ(metered_ev(1e30), -30.0f);
  EXPECT_EQ(metered_ev(0.0), 0.0f);
}

// A lit sphere in front of the camera, with a bright point light (as Blender writes one).
Scene lit_sphere(float light_intensity) {
  Scene s = test::camera_scene();
  s.camera.eye = Vec3(0, 0, 4);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.vertical_fov_deg = 40;
  s.meshes.push_back({"sphere", make_uv_sphere(1.0f, 48, 24)});
  Material m;
  m.diffuse = Color3(0.8f, 0.5f, 0.3f);
  m.ambient = Color3::Zero();
  m.specular = Color3(0.2f, 0.2f, 0.2f);
  m.shininess = 32;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  Light l;
  l.type = LightType::point;
  l.position = Vec3(2, 3, 4);
  l.constant_attenuation = 0;
  l.quadratic_attenuation = 1;
  l.diffuse = l.specular = Color3::Constant(light_intensity);
  s.lights = {l};
  return s;
}

std::vector<float> render_floats(const Scene& s, RenderOptions o, int w, int h, FrameStats* stats = nullptr) {
  std::vector<float> out(4 * std::size_t(w) * std::size_t(h));
  Renderer r;
  const ImageView v{out.data(), w, h, std::size_t(w) * 16, PixelFormat::rgba32f, false};
  EXPECT_TRUE(r.render(s, o, v, nullptr, stats).ok());
  return out;
}

TEST(Exposure, PlusOneStopDoublesTheLinearLight) {
  Scene s = lit_sphere(200.0f);
  RenderOptions o;
  o.hdr = true;  // float output with HDR: the exposure alone, no operator
  s.display.ev = 0.0f;
  s.display.tone_mapping = ToneMapping::neutral;  // not GL's display: the exposure path runs
  const std::vector<float> base = render_floats(s, o, 64, 48);
  s.display.ev = 1.0f;
  FrameStats stats;
  const std::vector<float> up = render_floats(s, o, 64, 48, &stats);
  EXPECT_EQ(stats.exposure_ev, 1.0f);
  std::size_t lit = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    if (i % 4 == 3) continue;
    if (base[i] > 0.0f) ++lit;
    ASSERT_EQ(up[i], 2.0f * base[i]) << "value " << i;
  }
  EXPECT_GT(lit, 500u);
  // Unclamped: the bright light gives values far above 1 before tone mapping.
  EXPECT_GT(*std::max_element(base.begin(), base.end()), 4.0f);
}

TEST(Exposure, AutomaticMetersTheDrawnPixelsToMiddleGreyWithTheSameBytesForAnyThreadCount) {
  Scene s = lit_sphere(5435.0f / float(std::numbers::pi));
  RenderOptions o;
  o.hdr = true;
  s.display.tone_mapping = ToneMapping::neutral;
  const int w = 96, h = 64;
  const std::vector<float> raw = render_floats(s, o, w, h);  // ev 0
  // The meter, in double, over the pixels that are not the (black) background.
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t p = 0; p < std::size_t(w) * std::size_t(h); ++p) {
    const float* c = &raw[4 * p];
    if (!(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] > 0.0)) continue;  // background and the unlit side
    sum += std::log(1e-4 + 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]);
    ++count;
  }
  ASSERT_GT(count, 1000u);
  s.display.automatic = true;
  o.hdr = false;
  o.threads = 1;
  FrameStats stats;
  Renderer r;
  test::Canvas one(w, h), three(w, h);
  ASSERT_TRUE(r.render(s, o, one.view(), nullptr, &stats).ok());
  // The highlight guard: the 98th percentile of the lit pixels' brightest channel maps to 0.95
  // after the neutral operator (1.712 before it); the exposure is the smaller of the two.
  std::vector<double> peaks;
  for (std::size_t p = 0; p < std::size_t(w) * std::size_t(h); ++p) {
    const float* c = &raw[4 * p];
    if (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] > 0.0) peaks.push_back(std::max({c[0], c[1], c[2]}));
  }
  std::sort(peaks.begin(), peaks.end());
  const double p98 = peaks[static_cast<std::size_t>(0.98 * double(peaks.size() - 1))];
  const double ev_average = std::log2(0.18 / std::exp(sum / double(count)));
  const double ev_reference = std::min(ev_average, std::log2(1.712 / p98));
  EXPECT_NEAR(stats.exposure_ev, ev_reference, 1e-4);
  EXPECT_FLOAT_EQ(highlight_ev(ToneMapping::neutral, p98), float(std::log2(1.712 / p98)));
  EXPECT_FLOAT_EQ(highlight_ev(ToneMapping::none, 0.95), 0.0f);
  EXPECT_FLOAT_EQ(highlight_ev(ToneMapping::aces, 2.863), 0.0f);
  // The operators map the guard's white to 0.95 (the constants solved from their formulas).
  EXPECT_NEAR(tone_map(ToneMapping::neutral, {1.712f, 1.712f, 1.712f})[0], 0.95f, 1e-3f);
  EXPECT_NEAR(tone_map(ToneMapping::aces, {2.863f, 2.863f, 2.863f})[0], 0.95f, 1e-3f);
  EXPECT_LT(stats.exposure_ev, -4.0f);
  o.threads = 3;
  FrameStats stats3;
  ASSERT_TRUE(r.render(s, o, three.view(), nullptr, &stats3).ok());
  EXPECT_EQ(stats3.exposure_ev, stats.exposure_ev);
  EXPECT_EQ(one.pixels(), three.pixels());
  // The subject is neither black nor clipped: most lit pixels between 10 % and 95 % of white.
  std::size_t lit = 0, mid = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int v = std::max({one.byte(x, y, 0), one.byte(x, y, 1), one.byte(x, y, 2)});
      if (v == 0) continue;
      ++lit;
      mid += v >= 26 && v <= 242;
    }
  }
  EXPECT_GT(double(mid), 0.8 * double(lit)) << mid << " of " << lit;
}

TEST(Exposure, BackgroundKeepsTheClearColourExactly) {
  Scene s = lit_sphere(400.0f);
  s.display.ev = -3.0f;
  s.display.tone_mapping = ToneMapping::aces;
  RenderOptions o;
  o.clear_color = {0.3f, 0.5f, 0.7f, 1.0f};
  test::Canvas with(64, 48);
  Renderer r;
  ASSERT_TRUE(r.render(s, o, with.view()).ok());
  s.display = Display{};  // GL's: the clear colour as it is
  test::Canvas gl(64, 48);
  ASSERT_TRUE(r.render(s, o, gl.view()).ok());
  for (int c = 0; c < 4; ++c) EXPECT_EQ(with.byte(0, 0, c), gl.byte(0, 0, c));
  EXPECT_NE(with.byte(32, 24, 0), gl.byte(32, 24, 0));  // the sphere's centre is exposed and tone-mapped
}

// The display pass's 8-bit store against its float output: every pixel of an exposed, tone-mapped
// frame in RGBA8 and BGRA8 (channels swapped), linear and sRGB-encoded, is the float frame's pixel
// encoded (to_unorm8, or the sRGB threshold search); background pixels too. On the scalar path (the
// scalar loop) and the simd path (the ISA's batches, and the scalar loop for a row's last pixels:
// the width is no multiple of a batch).
TEST(Exposure, EightBitStoreIsTheFloatFrameEncoded) {
  Scene s = lit_sphere(400.0f);
  s.display.ev = -2.0f;
  s.display.tone_mapping = ToneMapping::neutral;
  const int w = 67, h = 48;
  SrgbTable table;
  make_srgb_table(table);
  for (const LightingPath path : {LightingPath::scalar, LightingPath::simd})
  for (const bool srgb : {true, false}) {
    for (const PixelFormat format : {PixelFormat::rgba8, PixelFormat::bgra8}) {
      RenderOptions o;
      o.path = path;
      o.clear_color = {0.3f, 0.002f, 0.7f, 0.5f};
      const std::vector<float> floats = render_floats(s, o, w, h);  // not HDR: tone-mapped and clamped
      o.srgb = srgb;
      test::Canvas c(w, h, format);
      Renderer r;
      ASSERT_TRUE(r.render(s, o, c.view()).ok());
      int mismatches = 0;
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          for (int ch = 0; ch < 4; ++ch) {
            const float v = floats[(std::size_t(y) * w + x) * 4 + ch];
            const int expected = ch == 3 || !srgb ? to_unorm8(v) : srgb_unorm8_search(table.threshold, v);
            const int byte = format == PixelFormat::bgra8 && ch != 1 && ch != 3 ? 2 - ch : ch;
            mismatches += c.byte(x, y, byte) != expected;
          }
        }
      }
      EXPECT_EQ(mismatches, 0) << to_string(path) << (srgb ? " srgb " : " linear ") << to_string(format);
    }
  }
}

TEST(Exposure, IsValidatedWithItsField) {
  Scene s = lit_sphere(1.0f);
  s.display.ev = 40.0f;
  Status st = validate_scene(s);
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(st.field(), "display.ev");
  s.display.ev = std::nanf("");
  EXPECT_EQ(validate_scene(s).field(), "display.ev");
}

TEST(OutputEncoding, EightBitOutputIsSrgbByDefaultAndLinearOnRequest) {
  EXPECT_TRUE(RenderOptions{}.srgb);
  Scene s = test::camera_scene();
  test::add_quad(s, -10, -10, 10, 10, -2, Color3::Constant(0.5f));  // emissive 0.5 linear
  RenderOptions o;
  test::Canvas srgb(8, 8), linear(8, 8);
  Renderer r;
  ASSERT_TRUE(r.render(s, o, srgb.view()).ok());
  o.srgb = false;
  ASSERT_TRUE(r.render(s, o, linear.view()).ok());
  EXPECT_EQ(srgb.byte(4, 4, 0), 188);  // sRGB encoding of 0.5
  EXPECT_EQ(linear.byte(4, 4, 0), 128);
}

// An OBJ quad lit by nothing but its emission (illum 0: the diffuse colour, unlit), with a map_Kd
// of grey 128: an sRGB-encoded texel shows as 128 again in sRGB output.
TEST(OutputEncoding, MtlColourTexturesAreSrgb) {
  test::TempDir dir;
  // An uncompressed 4x4 TGA of grey 128: a format without an encoding tag (facet's PNGs carry an
  // sRGB chunk, which would decide the encoding by itself).
  std::string tga(18, '\0');
  tga[2] = 2, tga[12] = 4, tga[14] = 4, tga[16] = 32, tga[17] = 8;
  for (int i = 0; i < 16; ++i) tga += std::string("\x80\x80\x80\xff", 4);
  test::write_text(dir / "grey.tga", tga);
  test::write_text(dir / "quad.mtl", "newmtl m\nKd 1 1 1\nillum 0\nmap_Kd grey.tga\nmap_Ke grey.tga\n");
  test::write_text(dir / "quad.obj",
                   "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "usemtl m\nf 1/1 2/2 3/3 4/4\n");
  Result<Model> model = load_model(dir / "quad.obj");
  ASSERT_TRUE(model.ok()) << model.status().message();
  ASSERT_EQ(model->scene.textures.size(), 2u);
  EXPECT_EQ(model->scene.textures[0].encoding, TextureEncoding::srgb);  // map_Kd
  EXPECT_EQ(model->scene.textures[1].encoding, TextureEncoding::srgb);  // map_Ke
  EXPECT_EQ(model->scene.display.tone_mapping, ToneMapping::neutral);
  EXPECT_FALSE(model->scene.display.automatic);
}

// A glTF with KHR_lights_punctual in Blender's numbers (a 1000 W point light is 5,435 cd, a sun
// 683 lx): the model loads with automatic exposure and the neutral operator, and renders with its
// subject neither black nor clipped with no option given.
TEST(OutputEncoding, GltfLightsInPhysicalUnitsAreExposedAutomatically) {
  test::GltfBuilder b;
  const Mesh sphere = make_uv_sphere(1.0f, 32, 16);
  std::vector<float> pos, nrm;
  for (const Vec3& p : sphere.positions) pos.insert(pos.end(), {p.x(), p.y(), p.z()});
  for (const Vec3& n : sphere.normals) nrm.insert(nrm.end(), {n.x(), n.y(), n.z()});
  std::vector<std::uint32_t> idx;
  for (const auto& t : sphere.triangles) idx.insert(idx.end(), {t[0], t[1], t[2]});
  const int p = b.vec3(pos), n = b.vec3(nrm), i = b.indices32(idx);
  b.add("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}}}}});
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", p}, {"NORMAL", n}}}, {"indices", i}, {"material", 0}}}}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 5435.0}},
                                                          {{"type", "directional"}, {"intensity", 683.0}}};
  b.add("nodes", {{"mesh", 0}});
  b.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}, {"translation", {3.0, 4.0, 5.0}}});
  b.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}, {"rotation", {-0.3826834, 0.0, 0.0, 0.9238795}}});
  b.add("scenes", {{"nodes", {0, 1, 2}}});
  test::TempDir dir;
  test::write_text(dir / "lit.gltf", b.embedded());
  Result<Model> model = load_model(dir / "lit.gltf");
  ASSERT_TRUE(model.ok()) << model.status().message();
  EXPECT_TRUE(model->scene.display.automatic);
  EXPECT_EQ(model->scene.display.tone_mapping, ToneMapping::neutral);
  // intensity / pi (glTF's Lambert term against GL's).
  EXPECT_NEAR(model->scene.lights[0].diffuse.x(), 5435.0 / std::numbers::pi, 1e-2);
  Scene& s = model->scene;
  Result<Camera> cam = frame_scene(s, 1.5f);
  ASSERT_TRUE(cam.ok());
  s.camera = *cam;
  test::Canvas image(96, 64);
  Renderer r;
  FrameStats stats;
  ASSERT_TRUE(r.render(s, RenderOptions{}, image.view(), nullptr, &stats).ok());
  std::size_t covered = 0, mid = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 96; ++x) {
      const int v = std::max({image.byte(x, y, 0), image.byte(x, y, 1), image.byte(x, y, 2)});
      if (v == 0) continue;
      ++covered;
      mid += v >= 26 && v <= 242;
    }
  }
  EXPECT_GT(covered, 1000u);
  EXPECT_GT(double(mid), 0.6 * double(covered)) << mid << " of " << covered << ", ev " << stats.exposure_ev;
  // As GL read it (no exposure, clamped): a white silhouette.
  s.display = Display{};
  ASSERT_TRUE(r.render(s, RenderOptions{}, image.view()).ok());
  std::size_t white = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 96; ++x) white += image.byte(x, y, 0) == 255;
  }
  EXPECT_GT(double(white), 0.6 * double(covered));
}

TEST(SceneFile, ExposureAndToneMappingAreRead) {
  test::TempDir dir;
  test::write_text(dir / "a.json", R"({"exposure": "auto", "tone_mapping": "aces"})");
  Result<Scene> a = load_scene_file(dir / "a.json");
  ASSERT_TRUE(a.ok()) << a.status().message();
  EXPECT_TRUE(a->display.automatic);
  EXPECT_EQ(a->display.tone_mapping, ToneMapping::aces);
  test::write_text(dir / "b.json", R"({"exposure": -2.5})");
  Result<Scene> b = load_scene_file(dir / "b.json");
  ASSERT_TRUE(b.ok()) << b.status().message();
  EXPECT_EQ(b->display.ev, -2.5f);
  EXPECT_EQ(b->display.tone_mapping, ToneMapping::none);
  for (const char* bad : {R"({"exposure": "bright"})", R"({"exposure": 99})", R"({"tone_mapping": "reinhard"})", R"({"exposure": [1]})"}) {
    test::write_text(dir / "c.json", bad);
    Result<Scene> c = load_scene_file(dir / "c.json");
    ASSERT_FALSE(c.ok()) << bad;
    EXPECT_NE(c.status().message().find(std::string(bad).find("tone") != std::string::npos ? "tone_mapping" : "exposure"),
              std::string::npos)
        << c.status().message();
  }
}

}  // namespace
}  // namespace facet
