// The frame plan: lights that cannot reach an object are skipped, and skipping them changes no
// pixel.
#include <random>

#include "render_support.hpp"
#include "lighting/setup.hpp"

namespace facet {
namespace {

// Spheres spread over a 60 x 60 floor, 64 point lights scattered over it: 48 with a short range
// (each reaches one or two objects at most) and, if `far_lights`, 16 far away with strong
// attenuation.
Scene many_lights_scene(bool far_lights) {
  Scene s;
  s.meshes.push_back({"ball", make_uv_sphere(1.0f, 24, 12)});
  s.meshes.push_back({"floor", make_plane(60, 60, 30)});
  Material m;
  m.diffuse = Color3(0.7f, 0.7f, 0.7f);
  m.specular = Color3(0.5f, 0.5f, 0.5f);
  m.shininess = 32;
  s.materials.push_back(m);
  for (int i = 0; i < 16; ++i) {
    Mat4 t = Mat4::Identity();
    t.block<3, 1>(0, 3) = Vec3(-24.0f + 16.0f * float(i % 4), 1.0f, -24.0f + 16.0f * float(i / 4));
    s.objects.push_back({0, 0, t});
  }
  s.objects.push_back({1, 0, Mat4::Identity()});
  std::mt19937 rng(64);
  std::uniform_real_distribution<float> u(-28.0f, 28.0f), c(0.2f, 1.0f);
  for (int i = 0; i < (far_lights ? 64 : 48); ++i) {
    Light l;
    l.type = LightType::point;
    l.diffuse = l.specular = Color3(c(rng), c(rng), c(rng));
    if (i < 48) {
      l.position = Vec3(u(rng), 2.5f, u(rng));
      l.range = 4.0f;
    } else {  // far above, very strongly attenuated: bound ~ 3 / (1 + 50 * 400^2), far below the budget
      l.position = Vec3(u(rng), 400.0f, u(rng));
      l.quadratic_attenuation = 50.0f;
    }
    s.lights.push_back(l);
  }
  s.camera.eye = Vec3(0, 45, 40);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.far = 200;
  return s;
}

struct Renders {
  std::vector<std::uint8_t> culled, full;
  FrameStats culled_stats, full_stats;
};

Renders render_both(const Scene& s, LightingPath path, ShadingMode mode) {
  test::Canvas with(160, 120), without(160, 120);
  RenderOptions o;
  o.path = path;
  o.shading = mode;
  Renders r;
  Renderer renderer;
  EXPECT_TRUE(renderer.render(s, o, with.view(), nullptr, &r.culled_stats).ok());
  o.cull_lights = false;
  EXPECT_TRUE(renderer.render(s, o, without.view(), nullptr, &r.full_stats).ok());
  r.culled = with.pixels();
  r.full = without.pixels();
  return r;
}

// Lights beyond their range contribute exactly 0 (the window is 0 there), so skipping them
// cannot change a bit.
TEST(FramePlan, SkippingOutOfRangeLightsChangesNoPixel) {
  const Scene s = many_lights_scene(false);
  ASSERT_TRUE(validate_scene(s).ok());
  for (LightingPath path : {LightingPath::simd, LightingPath::scalar}) {
    for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      const Renders r = render_both(s, path, mode);
      EXPECT_TRUE(r.culled == r.full) << to_string(path) << " " << to_string(mode);
      EXPECT_EQ(r.full_stats.vertex_lights_skipped, 0u);
      // The floor is reached by every light; the spheres by one or two each. Per vertex most
      // pairs are skipped. Per pixel the floor's pixels dominate, and per triangle the floor's
      // triangles weigh more than their number: flat lights only triangles that cover a pixel
      // centre (2909 of this scene's 10248 triangles cover none).
      if (mode == ShadingMode::gouraud) {
        EXPECT_GT(r.culled_stats.vertex_lights_skipped, r.culled_stats.vertex_lights_evaluated);
      } else {
        EXPECT_GT(r.culled_stats.vertex_lights_skipped, 0u);
      }
      EXPECT_EQ(r.culled_stats.vertex_lights_evaluated + r.culled_stats.vertex_lights_skipped,
                r.full_stats.vertex_lights_evaluated);
    }
  }
}

// Lights skipped by the attenuation bound add, all together, less than half a step per channel:
// an 8-bit value can change only where the exact value lies that close to a rounding boundary,
// and then by one step.
TEST(FramePlan, SkippingFaintLightsChangesAPixelByOneStepAtMost) {
  const Scene s = many_lights_scene(true);
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    const Renders r = render_both(s, LightingPath::simd, mode);
    int worst = 0;
    std::size_t differing = 0;
    for (std::size_t i = 0; i < r.culled.size(); ++i) {
      const int d = std::abs(int(r.culled[i]) - int(r.full[i]));
      worst = std::max(worst, d);
      differing += d != 0;
    }
    EXPECT_LE(worst, 1) << to_string(mode);
    std::printf("%s: %zu of %zu channel values differ by one step\n", to_string(mode), differing, r.culled.size());
  }
}

TEST(FramePlan, LightsToDropUsesRangeAndTheAttenuationBudget) {
  Scene s = test::camera_scene();
  Material m;
  m.ambient = m.diffuse = m.specular = Color3(1, 1, 1);
  auto point = [](Vec3 p, float range, float k2) {
    Light l;
    l.type = LightType::point;
    l.position = p;
    l.range = range;
    l.quadratic_attenuation = k2;
    l.ambient = Color3(0.1f, 0.1f, 0.1f);
    return l;
  };
  s.lights = {point({0, 0, -20}, 9.0f, 0), point({0, 0, -20}, 11.0f, 0), point({0, 0, -200}, 0, 1e6f),
              point({0, 0, -12}, 0, 1)};
  s.lights.push_back(Light{});  // directional: never dropped
  const auto params = lighting::make_shade_params<double>(s, Eigen::Matrix4d::Identity(), m, true);
  const lighting::EyeSphere sphere{Eigen::Vector3d(0, 0, -10), 1.0};  // d_min: 9, 9, 189, 1
  std::vector<bool> drop;
  std::vector<lighting::CullCandidate> scratch;
  lighting::lights_to_drop(params, sphere, lighting::kLightCullBudget, drop, scratch);
  ASSERT_EQ(drop.size(), 5u);
  EXPECT_TRUE(drop[0]) << "range 9 ends exactly at the sphere";
  EXPECT_FALSE(drop[1]) << "range 11 reaches 2 units into it";
  EXPECT_TRUE(drop[2]) << "bound 2.1 / (1 + 1e6 * 189^2) is far below half a step";
  EXPECT_FALSE(drop[3]) << "bound 2.1 / 2 is not";
  EXPECT_FALSE(drop[4]);
}

// A linear-range light is zero from d = max + min on: dropped there, kept inside, its bound the
// attenuation at the sphere's nearest point.
TEST(FramePlan, LightsToDropUsesTheLinearRange) {
  Scene s = test::camera_scene();
  Material m;
  m.ambient = m.diffuse = m.specular = Color3(1, 1, 1);
  auto point = [](float min, float max) {
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0, 0, -20);
    l.attenuation_model = AttenuationModel::linear_range;
    l.range_min = min, l.range_max = max;
    l.ambient = Color3(0.1f, 0.1f, 0.1f);
    return l;
  };
  s.lights = {point(1, 8), point(1, 8.5f), point(0, 9), point(4.5f, 4.5f)};
  const auto params = lighting::make_shade_params<double>(s, Eigen::Matrix4d::Identity(), m, true);
  const lighting::EyeSphere sphere{Eigen::Vector3d(0, 0, -10), 1.0};  // d_min 9
  std::vector<bool> drop;
  std::vector<lighting::CullCandidate> scratch;
  lighting::lights_to_drop(params, sphere, lighting::kLightCullBudget, drop, scratch);
  ASSERT_EQ(drop.size(), 4u);
  EXPECT_TRUE(drop[0]) << "zero from 9 on";
  EXPECT_FALSE(drop[1]) << "zero from 9.5 on: bound 2.1 * 0.5 / 8.5";
  EXPECT_TRUE(drop[2]) << "min 0, max 9: zero from 9 on";
  EXPECT_TRUE(drop[3]) << "min = max = 4.5: zero from 9 on";
}

// The attenuation budget is spent in full and never overspent: four lights each bounded by 0.3
// of it, unattenuated (denominator 1), so three are dropped (0.9) and the fourth would cross it.
TEST(FramePlan, LightsToDropNeverSpendsMoreThanTheBudget) {
  Scene s = test::camera_scene();
  Material m;  // set-up multiplies the material into each light: diffuse 1 keeps the bound
  m.diffuse = Color3(1, 1, 1);
  const double bound = 0.3 * lighting::kLightCullBudget;
  for (int i = 0; i < 4; ++i) {
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0, 0, -20);
    l.ambient = l.specular = Color3::Zero();
    l.diffuse = Color3(float(bound), float(bound), float(bound));
    s.lights.push_back(l);
  }
  const auto params = lighting::make_shade_params<double>(s, Eigen::Matrix4d::Identity(), m, true);
  const lighting::EyeSphere sphere{Eigen::Vector3d(0, 0, -10), 1.0};
  std::vector<bool> drop;
  std::vector<lighting::CullCandidate> scratch;
  lighting::lights_to_drop(params, sphere, lighting::kLightCullBudget, drop, scratch);
  ASSERT_EQ(drop.size(), 4u);
  EXPECT_EQ(std::count(drop.begin(), drop.end(), true), 3);
  EXPECT_FALSE(drop[3]) << "ties are broken by light index";
}

}  // namespace
}  // namespace facet
