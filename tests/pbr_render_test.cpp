// PBR materials rendered (docs/pbr.md): the white furnace (an albedo-1 sphere in uniform light of
// 1 stays 1 at every roughness, metal and dielectric, per vertex and per pixel, on every path),
// a directional light on a plane against the BRDF's closed form per pixel, and the same bytes for
// any thread count with the studio's prefiltering on the renderer's threads.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "facet/facet.hpp"
#include "lighting/pbr.hpp"
#include "render_support.hpp"

namespace facet {
namespace {

std::vector<float> floats(const Scene& s, RenderOptions o, int w, int h) {
  std::vector<float> out(4 * std::size_t(w) * std::size_t(h), -1.0f);
  Renderer r;
  o.hdr = true;
  o.clear_color = {0.0f, 0.0f, 0.0f, 0.0f};  // drawn pixels have alpha 1
  const ImageView v{out.data(), w, h, std::size_t(w) * 16, PixelFormat::rgba32f, false};
  const Status st = r.render(s, o, v, nullptr, nullptr);
  EXPECT_TRUE(st.ok()) << st.message();
  return out;
}

Material pbr_material(Color3 base, float metallic, float roughness) {
  Material m;
  m.model = MaterialModel::pbr;
  m.base_color = base;
  m.metallic = metallic;
  m.roughness = roughness;
  return m;
}

// An orthographic camera at `eye` looking at the origin, `half_height` above and below the view.
void look_orthographic(Scene& s, const Vec3& eye, float half_height, float far) {
  s.camera.eye = eye;
  s.camera.target = Vec3(0, 0, 0);
  s.camera.projection = Projection::orthographic;
  s.camera.half_height = half_height;
  s.camera.near = 1;
  s.camera.far = far;
}

// Spheres of base colour 1 in a row per metallic value, roughness along the row, seen from the
// front by an orthographic camera.
Scene furnace_scene() {
  Scene s;
  look_orthographic(s, Vec3(0, 0, 10), 3.5f, 20);
  s.meshes.push_back({"ball", make_uv_sphere(1.0f, 48, 24)});
  const float metals[] = {0.0f, 0.5f, 1.0f}, roughs[] = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 5; ++j) {
      s.materials.push_back(pbr_material(Color3::Ones(), metals[i], roughs[j]));
      Instance inst{0, std::uint32_t(s.materials.size() - 1), Mat4::Identity()};
      inst.model.block<3, 1>(0, 3) = Vec3(2.2f * (j - 2), 2.2f * (1 - i), 0);
      s.objects.push_back(inst);
    }
  }
  s.global_ambient = Color3::Ones();
  return s;
}

// Every drawn pixel within `tolerance` of 1 in every channel; returns how many were drawn.
std::size_t expect_white(const std::vector<float>& px, float tolerance, const std::string& what) {
  std::size_t drawn = 0, bad = 0;
  float worst = 0.0f;
  for (std::size_t i = 0; i < px.size(); i += 4) {
    if (px[i + 3] == 0.0f) continue;
    ++drawn;
    for (int c = 0; c < 3; ++c) {
      const float e = std::abs(px[i + std::size_t(c)] - 1.0f);
      worst = std::max(worst, e);
      bad += e > tolerance ? 1 : 0;
    }
  }
  EXPECT_EQ(bad, 0u) << what << ": worst |colour - 1| " << worst;
  return drawn;
}

TEST(PbrFurnace, AnAlbedoOneSphereInUniformLightStaysWhite) {
  Scene s = furnace_scene();
  for (const auto& [path, isa] : test::every_path()) {
    for (ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong, ShadingMode::flat}) {
      RenderOptions o;
      o.path = path, o.isa = isa, o.shading = shading;
      const std::string what = std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading);
      // The scene's ambient as uniform radiance: the identity holds exactly (the split sum's terms
      // cancel), up to float rounding.
      const std::size_t drawn = expect_white(floats(s, o, 160, 112), 1e-4f, what + " ambient");
      EXPECT_GT(drawn, 15u * 400u) << what;
      // The same from an environment picture of 1: harmonics and prefiltered cube read it.
      // (The scene's ambient of 1 stays: with a picture PBR materials do not see it, or this were 2.)
      Scene image = s;
      image.environment_light.source = EnvironmentSource::image;
      image.environment_light.width = 64, image.environment_light.height = 32;
      image.environment_light.rgb.assign(64 * 32 * 3, 1.0f);
      expect_white(floats(image, o, 160, 112), 2e-3f, what + " image");
    }
  }
}

// Without the multiple-scattering term a rough white metal loses a third of the light: the
// furnace above tells the two apart (checked here so that the tolerance is known to matter).
TEST(PbrFurnace, SingleScatteringAloneWouldDarkenRoughMetal) {
  const lighting::pbr::Dfg d = lighting::pbr::dfg(0.5, 1.0, 4096);
  EXPECT_LT(d.scale + d.bias, 0.8);  // a white metal's single-scattering albedo at roughness 1
}

// A plane facing +z lit by a directional light, seen along -z by an orthographic camera and an
// infinite viewer: every pixel is E (n.l) f(l, v) with E = pi times the light's diffuse colour.
TEST(PbrClosedForm, DirectionalLightOnAPlaneIsTheBrdf) {
  const double pi = std::numbers::pi;
  struct Case {
    Color3 base;
    float metallic, roughness, tilt_deg, light_deg;
  };
  const Case cases[] = {{Color3(0.8f, 0.5f, 0.2f), 0.0f, 0.3f, 0.0f, 20.0f},
                        {Color3(0.8f, 0.5f, 0.2f), 1.0f, 0.3f, 25.0f, 40.0f},
                        {Color3(0.3f, 0.6f, 0.9f), 0.4f, 0.8f, 50.0f, 10.0f},
                        {Color3(1.0f, 1.0f, 1.0f), 0.0f, 0.05f, 10.0f, 15.0f}};
  for (const Case& c : cases) {
    Scene s;
    look_orthographic(s, Vec3(0, 0, 5), 0.5f, 10);
    s.viewer = ViewerMode::infinite;
    s.global_ambient = Color3::Zero();
    s.meshes.push_back({"plane", make_plane(4.0f, 4.0f, 1)});  // y up: turned to face +z below
    s.materials.push_back(pbr_material(c.base, c.metallic, c.roughness));
    const double t = (90.0 - c.tilt_deg) * pi / 180.0;  // the plane's normal tilted c.tilt_deg from +z about x
    Eigen::Matrix3f rot = Eigen::AngleAxisf(float(t), Eigen::Vector3f::UnitX()).toRotationMatrix();
    Mat4 model = Mat4::Identity();
    model.block<3, 3>(0, 0) = rot;
    s.objects.push_back({0, 0, model});
    const Vec3 n = (rot * Vec3(0, 1, 0)).normalized();
    const double a = c.light_deg * pi / 180.0;
    const Vec3 to_light(float(std::sin(a)), 0.3f, float(std::cos(a)));
    Light l;
    l.type = LightType::directional;
    l.direction = -to_light.normalized();
    l.diffuse = Color3(0.9f, 0.7f, 0.5f);
    s.lights.push_back(l);
    using V = lighting::V3<double>;
    lighting::pbr::Material<double> m;
    m.base_color = {c.base.x(), c.base.y(), c.base.z()};
    m.metallic = c.metallic;
    m.roughness = c.roughness;
    const Vec3 lu = to_light.normalized();
    const V f = lighting::pbr::brdf(m, V{n.x(), n.y(), n.z()}, V{lu.x(), lu.y(), lu.z()}, V{0.0, 0.0, 1.0});
    const double nl = double(n.dot(lu));
    const double expected[3] = {pi * 0.9 * nl * f.x, pi * 0.7 * nl * f.y, pi * 0.5 * nl * f.z};
    for (const auto& [path, isa] : test::every_path()) {
      for (ShadingMode shading : {ShadingMode::phong, ShadingMode::gouraud}) {
        RenderOptions o;
        o.path = path, o.isa = isa, o.shading = shading;
        const std::vector<float> px = floats(s, o, 24, 24);
        const double tolerance = path == LightingPath::reference ? 1e-6 : 1e-4;
        std::size_t drawn = 0;
        double worst = 0.0;
        for (std::size_t i = 0; i < px.size(); i += 4) {
          if (px[i + 3] == 0.0f) continue;
          ++drawn;
          for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(px[i + std::size_t(k)] - expected[k]) / expected[k]);
        }
        EXPECT_EQ(drawn, 24u * 24u) << c.tilt_deg;
        EXPECT_LT(worst, tolerance) << "metallic " << c.metallic << " roughness " << c.roughness << ", " << to_string(path) << " "
                                    << to_string(shading) << ": relative error " << worst;
      }
    }
  }
}

// A picture is read as three.js reads it: direction d at u = 1/2 + atan2(d.z, d.x) / 2 pi, so a
// bright band around the picture's centre column lights a rough white plane facing +X, and one a
// quarter from the left a plane facing -Z; planes facing the other way stay dark. (Each plane is
// seen head-on by an orthographic camera.)
TEST(PbrEnvironmentPicture, IsReadAsThreeJsReadsIt) {
  auto brightness = [](float band_u, const Vec3& facing) {
    Scene s;
    look_orthographic(s, 5.0f * facing, 0.5f, 10);
    s.meshes.push_back({"plane", make_plane(4.0f, 4.0f, 1)});
    s.materials.push_back(pbr_material(Color3::Ones(), 0.0f, 1.0f));
    // The plane's +y normal turned to `facing`.
    const Eigen::Quaternionf q = Eigen::Quaternionf::FromTwoVectors(Vec3(0, 1, 0), facing);
    Mat4 model = Mat4::Identity();
    model.block<3, 3>(0, 0) = q.toRotationMatrix();
    s.objects.push_back({0, 0, model});
    EnvironmentLight& e = s.environment_light;
    e.source = EnvironmentSource::image;
    e.width = 64, e.height = 32;
    e.rgb.assign(64 * 32 * 3, 0.05f);
    for (int r = 0; r < 32; ++r) {
      for (int c = 0; c < 64; ++c) {
        const float u = (c + 0.5f) / 64.0f;
        if (std::abs(u - band_u) < 0.1f) e.rgb[3 * std::size_t(r * 64 + c)] = e.rgb[3 * std::size_t(r * 64 + c) + 1] = e.rgb[3 * std::size_t(r * 64 + c) + 2] = 4.0f;
      }
    }
    RenderOptions o;
    o.shading = ShadingMode::phong;
    const std::vector<float> px = floats(s, o, 8, 8);
    return px[4 * (4 * 8 + 4)];
  };
  EXPECT_GT(brightness(0.5f, Vec3(1, 0, 0)), 4.0f * brightness(0.5f, Vec3(-1, 0, 0)));
  EXPECT_GT(brightness(0.25f, Vec3(0, 0, -1)), 4.0f * brightness(0.25f, Vec3(0, 0, 1)));
  EXPECT_GT(brightness(0.75f, Vec3(0, 0, 1)), 4.0f * brightness(0.75f, Vec3(0, 0, -1)));
  EXPECT_GT(brightness(0.0f, Vec3(-1, 0, 0)), 2.0f * brightness(0.0f, Vec3(1, 0, 0)));  // the band wraps at the edges
}

// A metallic-roughness map (per pixel) gives each pixel what the factors times its blue and green
// texels give an untextured material, on every path: a 2 x 1 map, metal and smooth on the left,
// dielectric and rough on the right, over a quad under a light and the studio.
TEST(PbrMetalRough, TheMapIsTheFactorsTimesItsTexels) {
  auto scene_with = [](const Material& m, bool textured) {
    Scene s;
    s.camera.eye = Vec3(0, 0, 3);
    s.camera.target = Vec3(0, 0, 0);
    s.camera.vertical_fov_deg = 30;
    s.environment_light.source = EnvironmentSource::studio;
    Mesh quad = make_plane(1.6f, 1.0f, 1);  // in y = 0: turned to face +z
    for (Vec3& p : quad.positions) p = Vec3(p.x(), -p.z(), 0.0f);
    for (Vec3& n : quad.normals) n = Vec3(0, 0, 1);
    s.meshes.push_back({"quad", quad});
    if (textured) {
      const std::uint8_t texels[8] = {0, 64, 255, 255, 0, 200, 0, 255};  // (r, g, b, a): left G 64 B 255, right G 200 B 0
      TextureOptions o;
      o.filter = TextureFilter::nearest;
      o.encoding = TextureEncoding::linear;
      Result<Texture> t = make_texture("mr", 2, 1, texels, o);
      EXPECT_TRUE(t.ok());
      s.textures.push_back(*t);
    }
    s.materials.push_back(m);
    s.objects.push_back({0, 0, Mat4::Identity()});
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0.5f, 0.8f, 2.0f);
    l.constant_attenuation = 0, l.quadratic_attenuation = 1;
    l.diffuse = Color3(2, 2, 2);
    s.lights.push_back(l);
    return s;
  };
  Material textured = pbr_material(Color3(0.9f, 0.5f, 0.3f), 0.8f, 0.9f);
  textured.metallic_roughness_texture = 0;
  Material left = textured, right = textured;
  left.metallic_roughness_texture = right.metallic_roughness_texture = kNoTexture;
  left.metallic = 0.8f * (255.0f / 255.0f), left.roughness = 0.9f * (64.0f / 255.0f);
  right.metallic = 0.0f, right.roughness = 0.9f * (200.0f / 255.0f);
  for (const auto& [path, isa] : test::every_path()) {
    RenderOptions o;
    o.path = path, o.isa = isa, o.shading = ShadingMode::phong;
    const int w = 64, h = 32;
    const std::vector<float> got = floats(scene_with(textured, true), o, w, h);
    const std::vector<float> l = floats(scene_with(left, false), o, w, h), r = floats(scene_with(right, false), o, w, h);
    std::size_t compared = 0, differ = 0;
    for (int y = 8; y < 24; ++y) {
      for (int x = 4; x < w - 4; ++x) {
        if (std::abs(x - w / 2) < 3) continue;  // the texels' edge
        const std::size_t i = 4 * (std::size_t(y) * w + std::size_t(x));
        const std::vector<float>& want = x < w / 2 ? l : r;
        for (int c = 0; c < 3; ++c) differ += std::abs(got[i + std::size_t(c)] - want[i + std::size_t(c)]) > 1e-6f * std::max(1.0f, want[i + std::size_t(c)]) ? 1 : 0;
        ++compared;
      }
    }
    EXPECT_GT(compared, 600u);
    EXPECT_EQ(differ, 0u) << to_string(path) << " " << to_string(isa);
    EXPECT_NE(l, r);
  }
}

// A ball over a plane under a sun at 45 degrees with ray-cast shadows and nothing else: the plane
// in the ball's shadow is black on every path and shading, beside it lit, and the paths agree.
TEST(PbrRender, ShadowsDarkenWhatTheyCover) {
  Scene s;
  look_orthographic(s, Vec3(0, 10, 0), 2.0f, 20);
  s.camera.up = Vec3(0, 0, -1);  // +x to the image's right
  s.meshes.push_back({"plane", make_plane(6.0f, 6.0f, 12)});
  s.meshes.push_back({"ball", make_uv_sphere(0.6f, 24, 12)});
  s.materials.push_back(pbr_material(Color3(0.8f, 0.8f, 0.8f), 0.0f, 0.5f));
  s.objects.push_back({0, 0, Mat4::Identity()});
  Instance ball{1, 0, Mat4::Identity()};
  ball.model(1, 3) = 1.0f;
  ball.model(0, 3) = 1.0f;  // off the view's centre, so the plane's centre is lit
  s.objects.push_back(ball);
  Light sun;  // directional, from above and +x
  sun.direction = Vec3(-1.0f, -1.0f, 0.0f).normalized();
  sun.diffuse = Color3(1.0f, 1.0f, 1.0f);
  sun.ambient = Color3::Zero();
  sun.shadow.method = ShadowMethod::raycast;
  s.lights.push_back(sun);
  s.global_ambient = Color3::Zero();
  for (ShadingMode shading : {ShadingMode::phong, ShadingMode::gouraud}) {
    std::vector<float> first;
    for (const auto& [path, isa] : test::every_path()) {
      RenderOptions o;
      o.path = path, o.isa = isa, o.shading = shading;
      const std::string what = std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading);
      const int w = 64, h = 64;
      const std::vector<float> px = floats(s, o, w, h);
      // 16 pixels a world unit, +x to the right: the ball's shadow falls around x = 0 (the
      // view's centre), the plane at x = -1.5 is lit.
      const float* shade = &px[4 * (std::size_t(h / 2) * w + std::size_t(w / 2))];
      const float* lit = &px[4 * (std::size_t(h / 2) * w + std::size_t(w / 2 - 24))];
      EXPECT_EQ(shade[0], 0.0f) << what;
      EXPECT_GT(lit[0], 0.2f) << what;
      if (first.empty()) first = px;
      float worst = 0.0f;
      for (std::size_t i = 0; i < px.size(); ++i) worst = std::max(worst, std::abs(px[i] - first[i]));
      EXPECT_LT(worst, 1e-3f) << what;
    }
  }
}

TEST(PbrRender, TheStudioGivesTheSameBytesForAnyThreadCount) {
  Scene s = furnace_scene();
  s.global_ambient = Color3::Zero();
  s.environment_light.source = EnvironmentSource::studio;
  for (Material& m : s.materials) m.base_color = Color3(0.9f, 0.6f, 0.3f);
  s.display.tone_mapping = ToneMapping::neutral;
  for (ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
    std::vector<std::uint8_t> first;
    for (int threads : {1, 2, 3, 8}) {
      RenderOptions o;
      o.shading = shading, o.threads = threads;
      std::vector<std::uint8_t> px(4 * 96 * 64);
      Renderer r;
      ASSERT_TRUE(r.render(s, o, ImageView{px.data(), 96, 64, 96 * 4, PixelFormat::rgba8, false}, nullptr, nullptr).ok());
      if (first.empty()) first = px;
      EXPECT_EQ(px, first) << threads << " threads, " << to_string(shading);
    }
  }
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// The surroundings count against the memory budget: a picture's prefiltered light is part of the
// frame's estimate when a PBR material or the backdrop reads it, and a budget below it refuses the
// frame by name before anything is built.
TEST(PbrRender, TheSurroundingsCountAgainstTheMemoryBudget) {
  Scene s = furnace_scene();
  s.environment_light.source = EnvironmentSource::image;
  s.environment_light.width = 1024, s.environment_light.height = 512;
  s.environment_light.rgb.assign(1024 * 512 * 3, 0.5f);
  RenderOptions o;
  const std::uint64_t with = estimate_frame_bytes(s, o, 64, 48);
  Scene gl = s;
  for (Material& m : gl.materials) m.model = MaterialModel::gl;
  const std::uint64_t without = estimate_frame_bytes(gl, o, 64, 48);
  EXPECT_GT(with, without + 1024u * 512u * 12u) << "the picture and its prefiltered cube";
  gl.background = Background::environment;
  EXPECT_GT(estimate_frame_bytes(gl, o, 64, 48), without + 1024u * 512u * 12u) << "the backdrop reads it too";
  o.memory_budget_bytes = (with + without) / 2;
  std::vector<float> out(4 * 64 * 48);
  Renderer r;
  const Status st = r.render(s, o, ImageView{out.data(), 64, 48, 64 * 16, PixelFormat::rgba32f, false}, nullptr, nullptr);
  EXPECT_EQ(st.code(), ErrorCode::out_of_memory);
  EXPECT_EQ(st.field(), "options.memory_budget_bytes");
  EXPECT_TRUE(r.render(s, RenderOptions{}, ImageView{out.data(), 64, 48, 64 * 16, PixelFormat::rgba32f, false}, nullptr, nullptr).ok());
}

}  // namespace
}  // namespace facet
