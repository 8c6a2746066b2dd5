// Drawing baked light (Instance::lightmap): the colour is the emission plus the material's diffuse
// colour (times its texture) times the lightmap's light times its scale, on every path, ISA and
// shading mode; the lights add only their specular (diffuse mode) or nothing (replace); a
// lightmapped object refuses what it cannot carry.
#include <algorithm>
#include <cmath>

#include "facet/bake.hpp"

#include "render_support.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

struct Pixel {
  int r, g, b, a;
};

Texture texture_of(int w, int h, const std::function<std::array<std::uint8_t, 4>(int, int)>& texel, TextureFilter filter) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto t = texel(x, y);
      for (int c = 0; c < 4; ++c) rgba[static_cast<std::size_t>(4 * (y * w + x) + c)] = t[static_cast<std::size_t>(c)];
    }
  TextureOptions o{filter, TextureWrap::clamp};
  o.encoding = TextureEncoding::linear;
  Result<Texture> t = make_texture("t", w, h, rgba, o);
  EXPECT_TRUE(t.ok()) << t.status().message();
  return std::move(*t);
}

// A quad filling the view's centre, diffuse (0.5, 0.8, 1.0), lit by a white directional light
// straight on, with a uniform lightmap of (96, 160, 64) / 255 and scale 2.
Scene lightmapped_quad() {
  Scene s = test::camera_scene();
  test::add_quad(s, -2, -2, 2, 2, -3, Color3::Zero());
  Material& m = s.materials[0];
  m.diffuse = Color3(0.5f, 0.8f, 1.0f);
  m.ambient = Color3(1, 1, 1);
  Mesh& mesh = s.meshes[0].mesh;
  mesh.lightmap_uvs = {Vec2(0.1f, 0.1f), Vec2(0.9f, 0.1f), Vec2(0.9f, 0.9f), Vec2(0.1f, 0.9f)};
  s.textures.push_back(texture_of(4, 4, [](int, int) { return std::array<std::uint8_t, 4>{96, 160, 64, 255}; }, TextureFilter::bilinear));
  s.objects[0].lightmap = 0;
  s.objects[0].lightmap_scale = 2.0f;
  Light l;
  l.type = LightType::directional;
  l.direction = Vec3(0, 0, -1);
  s.lights.push_back(l);
  s.global_ambient = Color3(0.3f, 0.3f, 0.3f);  // must not show: the lightmap stands for ambient light
  return s;
}

Pixel render_centre(const Scene& s, LightingPath path, Isa isa, ShadingMode mode) {
  test::Canvas c(32, 32);
  RenderOptions o = test::gl_options();
  o.path = path, o.isa = isa, o.shading = mode;
  Renderer r;
  const Status st = r.render(s, o, c.view());
  EXPECT_TRUE(st.ok()) << st.message();
  return {c.byte(16, 16, 0), c.byte(16, 16, 1), c.byte(16, 16, 2), c.byte(16, 16, 3)};
}

int step(double v) { return static_cast<int>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); }

TEST(LightmapRender, ColourIsAlbedoTimesBakedLight) {
  const Scene s = lightmapped_quad();
  const double light[3] = {2.0 * 96 / 255, 2.0 * 160 / 255, 2.0 * 64 / 255};
  const double albedo[3] = {0.5, 0.8, 1.0};
  for (const auto& [path, isa] : test::every_path()) {
    for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      const Pixel p = render_centre(s, path, isa, mode);
      EXPECT_NEAR(p.r, step(albedo[0] * light[0]), 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
      EXPECT_NEAR(p.g, step(albedo[1] * light[1]), 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
      EXPECT_NEAR(p.b, step(albedo[2] * light[2]), 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
    }
  }
}

TEST(LightmapRender, TextureModulatesAndEmissionAdds) {
  Scene s = lightmapped_quad();
  s.meshes[0].mesh.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  s.textures.push_back(texture_of(2, 2, [](int, int) { return std::array<std::uint8_t, 4>{255, 128, 51, 255}; }, TextureFilter::nearest));
  s.materials[0].diffuse_texture = 1;
  s.materials[0].emissive = Color3(0.1f, 0.0f, 0.05f);
  const double light[3] = {2.0 * 96 / 255, 2.0 * 160 / 255, 2.0 * 64 / 255};
  const double albedo[3] = {0.5, 0.8, 1.0}, tex[3] = {1.0, 128.0 / 255, 51.0 / 255}, e[3] = {0.1, 0.0, 0.05};
  for (const auto& [path, isa] : test::every_path()) {
    for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      const Pixel p = render_centre(s, path, isa, mode);
      // The emission is in the lit colour, so the texture modulates it too (GL_MODULATE).
      const int expected[3] = {step((e[0] + albedo[0] * light[0]) * tex[0]), step((e[1] + albedo[1] * light[1]) * tex[1]),
                               step((e[2] + albedo[2] * light[2]) * tex[2])};
      EXPECT_NEAR(p.r, expected[0], 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
      EXPECT_NEAR(p.g, expected[1], 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
      EXPECT_NEAR(p.b, expected[2], 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
    }
  }
}

TEST(LightmapRender, LightsAddTheirSpecularOnlyInDiffuseMode) {
  Scene s = lightmapped_quad();
  s.materials[0].specular = Color3(0.25f, 0.25f, 0.25f);
  s.materials[0].shininess = 1;  // a broad lobe: n.h is 1 at the centre (light and viewer straight on)
  s.lights[0].specular = Color3(1, 1, 1);
  const double light[3] = {2.0 * 96 / 255, 2.0 * 160 / 255, 2.0 * 64 / 255};
  const double albedo[3] = {0.5, 0.8, 1.0};
  for (LightmapMode mode : {LightmapMode::diffuse, LightmapMode::replace}) {
    s.objects[0].lightmap_mode = mode;
    const double spec = mode == LightmapMode::diffuse ? 0.25 : 0.0;
    for (const auto& [path, isa] : test::every_path()) {
      const Pixel p = render_centre(s, path, isa, ShadingMode::phong);
      EXPECT_NEAR(p.r, step(albedo[0] * light[0] + spec), 1) << to_string(mode) << " " << to_string(path) << " " << to_string(isa);
      EXPECT_NEAR(p.g, step(albedo[1] * light[1] + spec), 1) << to_string(mode) << " " << to_string(path) << " " << to_string(isa);
      EXPECT_NEAR(p.b, step(albedo[2] * light[2] + spec), 1) << to_string(mode) << " " << to_string(path) << " " << to_string(isa);
    }
  }
}

// A lightmap with a gradient, on a quad seen at an angle (perspective-correct lookup): every path
// and ISA within a step of the scalar path, and the picture follows the map.
TEST(LightmapRender, GradientIsTheSameOnEveryPath) {
  Scene s = lightmapped_quad();
  s.meshes[0].mesh.positions = {Vec3(-3, -2, -2), Vec3(3, -2, -6), Vec3(3, 2, -6), Vec3(-3, 2, -2)};
  s.textures[0] = texture_of(16, 16, [](int x, int y) {
    return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(16 * x), static_cast<std::uint8_t>(16 * y), 128, 255};
  }, TextureFilter::bilinear);
  s.objects[0].lightmap_scale = 1.0f;
  auto render = [&](LightingPath path, Isa isa, ShadingMode mode) {
    test::Canvas c(64, 48);
    RenderOptions o = test::gl_options();
    o.path = path, o.isa = isa, o.shading = mode;
    Renderer r;
    EXPECT_TRUE(r.render(s, o, c.view()).ok());
    return c.pixels();
  };
  for (ShadingMode mode : {ShadingMode::gouraud, ShadingMode::phong}) {
    const auto scalar = render(LightingPath::scalar, Isa::best, mode);
    for (const auto& [path, isa] : test::every_path()) {
      const auto other = render(path, isa, mode);
      int worst = 0;
      for (std::size_t i = 0; i < scalar.size(); ++i) worst = std::max(worst, std::abs(int(scalar[i]) - int(other[i])));
      EXPECT_LE(worst, 1) << to_string(path) << " " << to_string(isa) << " " << to_string(mode);
    }
    // Red grows with u, to the right; green with the texel row, whose first (the image's top) is
    // at v = 1: green falls upwards. The quad covers columns 0-44 and, near the middle, rows 12-36.
    test::Canvas c(64, 48);
    RenderOptions o = test::gl_options();
    o.shading = mode;
    Renderer r;
    ASSERT_TRUE(r.render(s, o, c.view()).ok());
    EXPECT_LT(c.byte(8, 24, 0) + 20, c.byte(40, 24, 0));
    EXPECT_LT(c.byte(24, 16, 1) + 20, c.byte(24, 32, 1));
  }
}

// Bake and draw: a floor under a point light, baked (direct light only) and drawn from its
// lightmap, against the same light computed per pixel by the renderer (Phong): the lightmap's
// footprint averages, bilinear lookup and 8-bit storage cost at most a few steps.
TEST(LightmapRender, BakedDirectLightMatchesPerPixelLighting) {
  Scene s = test::camera_scene();
  s.camera.eye = Vec3(0, 3, 2.5f);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.vertical_fov_deg = 50;
  Mesh floor = make_plane(3.0f, 3.0f, 6);
  floor.uvs.clear(), floor.tangents.clear();
  s.meshes.push_back({"floor", floor});
  Material m;
  m.ambient = Color3::Zero(), m.specular = Color3::Zero();
  m.diffuse = Color3(0.6f, 0.5f, 0.4f);
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  Light l;
  l.type = LightType::point;
  l.position = Vec3(0.4f, 1.2f, -0.3f);
  l.diffuse = Color3(0.9f, 0.8f, 0.7f);
  l.ambient = Color3::Zero();
  l.quadratic_attenuation = 0.5f;
  s.lights.push_back(l);
  BakeOptions o;
  o.charts.texels_per_unit = 32;
  o.radiosity = false;
  const Result<BakeResult> baked = bake_lightmaps(s, o);
  ASSERT_TRUE(baked.ok()) << baked.status().message();
  const BakedLightmap& lm = baked->lightmaps[0];
  // The lightmap as an 8-bit texture (rows top first: texture row 0 is v = 1), scaled by its largest value.
  float scale = 0;
  for (const Color3& c : lm.light) scale = std::max(scale, c.maxCoeff());
  const int w = lm.unwrap.width, h = lm.unwrap.height;
  Scene lit = s;
  lit.textures.push_back(texture_of(w, h, [&](int x, int y) {
    const Color3& c = lm.light[static_cast<std::size_t>((h - 1 - y) * w + x)];
    std::array<std::uint8_t, 4> t{};
    for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(255.0 * c[k] / scale));
    t[3] = 255;
    return t;
  }, TextureFilter::bilinear));
  Result<Mesh> split = with_lightmap_uvs(floor, lm.unwrap);
  ASSERT_TRUE(split.ok()) << split.status().message();
  lit.meshes[0].mesh = std::move(*split);
  lit.objects[0].lightmap = 0;
  lit.objects[0].lightmap_scale = scale;
  lit.objects[0].lightmap_mode = LightmapMode::replace;
  auto render = [](const Scene& scene) {
    test::Canvas c(160, 120);
    RenderOptions ro = test::gl_options();
    ro.shading = ShadingMode::phong;
    Renderer r;
    EXPECT_TRUE(r.render(scene, ro, c.view()).ok());
    return c.pixels();
  };
  const auto per_pixel = render(s), from_lightmap = render(lit);
  int worst = 0;
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < per_pixel.size(); i += 4) {
    for (std::size_t k = 0; k < 3; ++k) {
      const int d = std::abs(int(per_pixel[i + k]) - int(from_lightmap[i + k]));
      worst = std::max(worst, d);
      sum += d, ++n;
    }
  }
  std::printf("baked against per-pixel: mean %.3f steps, largest %d\n", sum / double(n), worst);
  // Measured: mean 0.018 steps, largest 1.
  EXPECT_LE(sum / double(n), 0.25);
  EXPECT_LE(worst, 2);
  // The light falls off across the floor: the comparison is not between two flat pictures.
  const auto [lo, hi] = std::minmax_element(per_pixel.begin(), per_pixel.end());
  EXPECT_GT(int(*hi) - int(*lo), 100);
}

TEST(LightmapRender, RefusesWhatALightmappedObjectCannotCarry) {
  auto field = [](const Scene& s) { return validate_scene(s).field(); };
  const Scene base = lightmapped_quad();
  ASSERT_TRUE(validate_scene(base).ok()) << validate_scene(base).message();
  Scene s = base;
  s.objects[0].lightmap = 5;
  EXPECT_EQ(field(s), "objects[0].lightmap");
  s = base;
  s.objects[0].lightmap_scale = 0;
  EXPECT_EQ(field(s), "objects[0].lightmap_scale");
  s = base;
  s.meshes[0].mesh.lightmap_uvs.clear();
  EXPECT_EQ(field(s), "objects[0].lightmap");
  s = base;
  s.meshes[0].mesh.lightmap_uvs.pop_back();
  EXPECT_EQ(field(s), "meshes[0].lightmap_uvs");
  s = base;
  s.meshes[0].mesh.lightmap_uvs[1].x() = std::nanf("");
  EXPECT_EQ(field(s), "meshes[0].lightmap_uvs[1]");
  s = base;
  s.meshes[0].mesh.colors.assign(4, Color3(1, 1, 1));
  EXPECT_EQ(field(s), "objects[0].lightmap");
  s = base;
  s.materials[0].environment.mode = EnvironmentMode::sphere;
  s.materials[0].environment.maps[0] = 0;
  EXPECT_EQ(field(s), "objects[0].lightmap");
  s = base;
  s.meshes[0].mesh.uvs.assign(4, Vec2(0, 0));
  s.materials[0].diffuse_texture = 0;
  s.materials[0].texture_mode = TextureMode::decal;
  EXPECT_EQ(field(s), "objects[0].lightmap");
}

// What cannot draw with a lightmap is refused before a bake starts (it used to bake, and then the
// baked scene file could not be read): a glTF with a normal map, and vertex colours.
TEST(LightmapRefusal, BakeRefusesWhatCannotCarryALightmapBeforeAnyWork) {
  Result<Model> as_pbr = load_model(test::data_dir() + "/gltf/relief_cube.gltf");
  ASSERT_TRUE(as_pbr.ok()) << as_pbr.status().message();
  Result<BakeResult> pbr = bake_lightmaps(as_pbr->scene);
  ASSERT_FALSE(pbr.ok());
  EXPECT_NE(pbr.status().message().find("materials[0] is a pbr material, which facet does not lightmap"), std::string::npos)
      << pbr.status().message();
  ModelOptions gl;
  gl.gl_materials = true;
  Result<Model> relief = load_model(test::data_dir() + "/gltf/relief_cube.gltf", gl);
  ASSERT_TRUE(relief.ok()) << relief.status().message();
  Result<BakeResult> r = bake_lightmaps(relief->scene);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().field(), "objects[0].lightmap");
  EXPECT_NE(r.status().message().find("cannot bake: objects[0].lightmap: material materials[0] has an environment, normal or bump map"),
            std::string::npos)
      << r.status().message();
  EXPECT_EQ(check_lightmap_object(relief->scene, 0).field(), "objects[0].lightmap");
  Scene coloured;
  coloured.meshes.push_back({"q", make_plane(1.0f, 1.0f, 1)});
  coloured.meshes[0].mesh.colors.assign(coloured.meshes[0].mesh.positions.size(), Color3(1, 0, 0));
  coloured.materials.push_back(Material{});
  coloured.objects.push_back(Instance{});
  EXPECT_NE(check_lightmap_object(coloured, 0).message().find("vertex colours"), std::string::npos);
  coloured.meshes[0].mesh.colors.clear();
  EXPECT_TRUE(check_lightmap_object(coloured, 0).ok());
  EXPECT_FALSE(check_lightmap_object(coloured, 1).ok()) << "an object out of range";
}

}  // namespace
}  // namespace facet
