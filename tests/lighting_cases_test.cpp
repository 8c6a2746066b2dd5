// The lighting equation case by case, on one vertex, with expected values worked out by hand (the
// derivation is in each comment), run on every lighting path. World space = eye space here (see
// eye_space_scene), except in the transform cases, which check that camera and model transforms
// leave those values unchanged.
#include <cmath>
#include <limits>
#include <numbers>

#include "test_support.hpp"

namespace facet {
namespace {

using test::eye_space_scene;
using test::set_single_vertex;

constexpr float kTolerance = 1e-6f;
const double kInvSqrt2 = 1.0 / std::sqrt(2.0);

Light directional_towards(const Vec3& to_light) {
  Light l;
  l.type = LightType::directional;
  l.direction = -to_light;
  l.diffuse = l.specular = Color3::Ones();
  return l;
}

Light point_at(const Vec3& position) {
  Light l;
  l.type = LightType::point;
  l.position = position;
  l.diffuse = l.specular = Color3::Ones();
  return l;
}

// Every path; the simd path on each ISA with the exact pow tier (the hand values are exact, to
// 1e-6) and with the auto and fast tiers, whose float kernel uses refined reciprocal estimates and
// cheaper pow methods (to 3e-5 relative: fast pow's contract is 2.2e-5).
struct PathCase {
  LightingPath path;
  Isa isa;
  PowTier tier = PowTier::exact;
};

std::string name_of(const PathCase& c) {
  if (c.path != LightingPath::simd) return to_string(c.path);
  return std::string("simd_") + to_string(c.isa) + (c.tier == PowTier::exact ? "" : std::string("_") + to_string(c.tier));
}

class LightingCase : public ::testing::TestWithParam<PathCase> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam().isa)) GTEST_SKIP() << "this CPU has no " << to_string(GetParam().isa);
  }
  Scene scene = eye_space_scene();
  Material& material() { return scene.materials[0]; }

  LightingOptions options_for_path() const {
    LightingOptions options;
    options.path = GetParam().path;
    options.isa = GetParam().isa;
    options.pow_tier = GetParam().tier;
    return options;
  }
  double tolerance(double expected) const {
    return GetParam().tier == PowTier::exact ? kTolerance : 3e-5 * std::max(1.0, std::abs(expected));
  }

  VertexColors light(const Vec3& p, const Vec3& n, bool clamp = true) {
    set_single_vertex(scene, p, n);
    LightingOptions options = options_for_path();
    options.clamp = clamp;
    VertexColors out;
    const Status s = light_instance(scene, 0, options, out);
    EXPECT_TRUE(s.ok()) << s.message();
    return out;
  }
  Color3 front(const Vec3& p, const Vec3& n, bool clamp = true) {
    VertexColors c = light(p, n, clamp);
    return c.front.empty() ? Color3::Constant(-1.0f) : c.front[0];
  }
};

#define EXPECT_COLOR(actual, r, g, b)                                                  \
  do {                                                                                 \
    const Color3 a_ = (actual);                                                        \
    EXPECT_NEAR(a_.x(), (r), tolerance(r));                                            \
    EXPECT_NEAR(a_.y(), (g), tolerance(g));                                            \
    EXPECT_NEAR(a_.z(), (b), tolerance(b));                                            \
  } while (0)
#define EXPECT_GREY(actual, v) EXPECT_COLOR(actual, v, v, v)

const Vec3 kOrigin(0, 0, -3);  // a vertex in front of the eye
const Vec3 kFacingEye(0, 0, 1);

TEST_P(LightingCase, EmissiveOnly) {
  material().emissive = Color3(0.1f, 0.2f, 0.3f);
  scene.global_ambient = Color3(1, 1, 1);  // a_m = 0: no ambient
  EXPECT_COLOR(front(kOrigin, kFacingEye), 0.1, 0.2, 0.3);
}

TEST_P(LightingCase, GlobalAmbientOnly) {
  material().ambient = Color3(0.5f, 0.4f, 0.2f);
  scene.global_ambient = Color3(0.2f, 0.5f, 1.0f);
  // a_m * a_scene = (0.5*0.2, 0.4*0.5, 0.2*1.0)
  EXPECT_COLOR(front(kOrigin, kFacingEye), 0.1, 0.2, 0.2);
}

TEST_P(LightingCase, LightAmbientIsAddedEvenFacingAway) {
  material().ambient = Color3(0.5f, 0.5f, 0.5f);
  material().diffuse = Color3::Ones();
  Light l = directional_towards(Vec3(0, 0, 1));
  l.ambient = Color3(0.4f, 0.2f, 0.0f);
  scene.lights.push_back(l);
  // Normal points away from the light: no diffuse; a_m * a_i = (0.2, 0.1, 0).
  EXPECT_COLOR(front(kOrigin, Vec3(0, 0, -1)), 0.2, 0.1, 0.0);
}

TEST_P(LightingCase, DiffuseHeadOn) {
  material().diffuse = Color3(0.8f, 0.6f, 0.4f);
  Light l = directional_towards(Vec3(0, 0, 1));
  l.diffuse = Color3(0.5f, 1.0f, 1.0f);
  scene.lights.push_back(l);
  // n.VP = 1: d_m * d_i = (0.4, 0.6, 0.4)
  EXPECT_COLOR(front(kOrigin, kFacingEye), 0.4, 0.6, 0.4);
}

TEST_P(LightingCase, DiffuseAt60Degrees) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  // cos 60 = 0.5
  const float s = std::sin(std::numbers::pi_v<float> / 3), c = std::cos(std::numbers::pi_v<float> / 3);
  EXPECT_GREY(front(kOrigin, Vec3(s, 0, c)), 0.5);
}

TEST_P(LightingCase, DiffuseAt45Degrees) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(directional_towards(Vec3(0, 1, 1)));
  // VP = (0, 1, 1)/sqrt 2, n = z: cos 45 = 0.70710678
  EXPECT_GREY(front(kOrigin, kFacingEye), kInvSqrt2);
}

TEST_P(LightingCase, DiffuseAtGrazingAndBehindIsZero) {
  material().diffuse = Color3::Ones();
  material().specular = Color3::Ones();
  scene.lights.push_back(directional_towards(Vec3(1, 0, 0)));
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);                 // 90 deg: n.VP = 0, f = 0
  EXPECT_GREY(front(kOrigin, Vec3(-0.5f, 0, 0.8660254f)), 0.0);  // 120 deg
}

TEST_P(LightingCase, SpecularInfiniteViewer) {
  material().specular = Color3(1.0f, 0.5f, 0.25f);
  material().shininess = 10;
  scene.viewer = ViewerMode::infinite;
  scene.lights.push_back(directional_towards(Vec3(0, 1, 1)));
  // h = VP + (0,0,1) lies 22.5 deg from n = z: (cos 22.5)^10 = 0.45305764
  const double spec = std::pow(std::cos(std::numbers::pi / 8), 10);
  EXPECT_COLOR(front(kOrigin, kFacingEye), spec, 0.5 * spec, 0.25 * spec);
}

TEST_P(LightingCase, SpecularLocalViewerUsesDirectionToEye) {
  material().specular = Color3::Ones();
  material().shininess = 4;
  scene.viewer = ViewerMode::local;
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  // V = (3, 0, -4): unit(V->eye) = (-0.6, 0, 0.8); h ~ (-0.6, 0, 1.8); (n.h)^2 = 3.24/3.6 = 0.9,
  // so (n.h)^4 = 0.81.
  EXPECT_GREY(front(Vec3(3, 0, -4), kFacingEye), 0.81);
}

TEST_P(LightingCase, SpecularInfiniteViewerIgnoresPosition) {
  material().specular = Color3::Ones();
  material().shininess = 4;
  scene.viewer = ViewerMode::infinite;
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  // Same vertex as above, but h = (0, 0, 2): n.h = 1.
  EXPECT_GREY(front(Vec3(3, 0, -4), kFacingEye), 1.0);
}

TEST_P(LightingCase, ZeroToTheZeroIsOne) {
  material().specular = Color3(0.6f, 0.6f, 0.6f);
  material().shininess = 0;
  scene.viewer = ViewerMode::infinite;
  scene.lights.push_back(directional_towards(Vec3(1, 0, 0)));
  // n = (1, 0, -1)/sqrt 2: n.VP = 0.707 > 0 so f = 1; h ~ (1, 0, 1) is perpendicular to n, so
  // n.h = 0 and 0^0 = 1: specular = s_m s_i = 0.6.
  const Vec3 n(static_cast<float>(kInvSqrt2), 0, static_cast<float>(-kInvSqrt2));
  EXPECT_GREY(front(kOrigin, n), 0.6);
  material().shininess = 1;  // 0^1 = 0
  EXPECT_GREY(front(kOrigin, n), 0.0);
}

TEST_P(LightingCase, NoHighlightOnTheUnlitSide) {
  material().specular = Color3::Ones();
  material().shininess = 1;
  scene.viewer = ViewerMode::infinite;
  scene.lights.push_back(directional_towards(Vec3(1, 0, -0.1f)));
  // n.VP < 0 so f = 0, although n.h > 0 (h ~ (1, 0, 0.9)).
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);
}

TEST_P(LightingCase, PointLightDirection) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(point_at(Vec3(3, 0, 1)));
  // From V = (0,0,-3) to P = (3,0,1): (3,0,4), d = 5, VP = (0.6, 0, 0.8): n.VP = 0.8.
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.8);
}

TEST_P(LightingCase, PointLightAttenuation) {
  material().diffuse = Color3::Ones();
  Light l = point_at(Vec3(0, 0, -1));
  l.constant_attenuation = 1.0f;
  l.linear_attenuation = 0.5f;
  l.quadratic_attenuation = 0.25f;
  scene.lights.push_back(l);
  // d = 2: 1 / (1 + 0.5*2 + 0.25*4) = 1/3.
  EXPECT_GREY(front(kOrigin, kFacingEye), 1.0 / 3.0);
}

TEST_P(LightingCase, AttenuationAlsoScalesLightAmbient) {
  material().ambient = Color3::Ones();
  Light l = point_at(Vec3(0, 0, -1));
  l.ambient = Color3(0.6f, 0.6f, 0.6f);
  l.quadratic_attenuation = 0.5f;  // k0 = 1: 1 / (1 + 0.5*4) = 1/3
  scene.lights.push_back(l);
  EXPECT_GREY(front(kOrigin, Vec3(0, 0, -1)), 0.2);
}

Light spot_down_z(float cutoff_deg, float exponent) {
  Light l = point_at(Vec3(0, 0, 0));
  l.type = LightType::spot;
  l.direction = Vec3(0, 0, -1);
  l.spot_cutoff_deg = cutoff_deg;
  l.spot_exponent = exponent;
  return l;
}

TEST_P(LightingCase, SpotInsideCone) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(spot_down_z(30, 2));
  // V = (1, 0, -4): cos(angle to axis) = 4/sqrt 17 (14 deg, inside 30), spot = 16/17;
  // n.VP = 4/sqrt 17; colour = (4/sqrt 17)^3 = 0.91307529.
  EXPECT_GREY(front(Vec3(1, 0, -4), kFacingEye), std::pow(4.0 / std::sqrt(17.0), 3));
}

TEST_P(LightingCase, SpotOutsideConeGivesNothingNotEvenAmbient) {
  material().diffuse = Color3::Ones();
  material().ambient = Color3::Ones();
  Light l = spot_down_z(30, 2);
  l.ambient = Color3::Ones();
  scene.lights.push_back(l);
  // V = (3, 0, -4): 36.9 deg from the axis, outside 30.
  EXPECT_GREY(front(Vec3(3, 0, -4), kFacingEye), 0.0);
}

TEST_P(LightingCase, SpotConeEdgeIsInside) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(spot_down_z(90, 0));
  // V = (1, 0, 0) is exactly 90 deg from the axis: cos = 0 >= cos(90) = 0, inside; 0^0 = 1.
  // VP = (-1, 0, 0) and n = (-1, 0, 0): diffuse 1.
  EXPECT_GREY(front(Vec3(1, 0, 0), Vec3(-1, 0, 0)), 1.0);
  // A hair beyond the edge: outside.
  EXPECT_GREY(front(Vec3(1, 0, 0.01f), Vec3(-1, 0, 0)), 0.0);
}

TEST_P(LightingCase, SpotWithCutoff180IsAPointLight) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(spot_down_z(180, 50));
  // Behind the spot (V = (0,0,3)): no cone, no exponent applied.
  EXPECT_GREY(front(Vec3(0, 0, 3), Vec3(0, 0, -1)), 1.0);
}

Light smooth_spot(float inner, float outer, float falloff) {
  Light l = spot_down_z(45, 0);
  l.spot_shape = SpotShape::smooth_cone;
  l.spot_inner_deg = inner;
  l.spot_outer_deg = outer;
  l.spot_falloff = falloff;
  return l;
}

Vec3 at_angle_deg(double deg, double dist) {
  const double r = deg * std::numbers::pi / 180.0;
  return Vec3(static_cast<float>(dist * std::sin(r)), 0, static_cast<float>(-dist * std::cos(r)));
}

TEST_P(LightingCase, DualConeRamp) {
  material().ambient = Color3::Ones();
  Light l = smooth_spot(20, 40, 2);
  l.ambient = Color3::Ones();
  l.diffuse = Color3::Zero();
  scene.lights.push_back(l);
  // 30 deg: t = (cos30 - cos40)/(cos20 - cos40) = 0.57576741, spot = t^2 = 0.33150810.
  const double t = (std::cos(std::numbers::pi / 6) - std::cos(40 * std::numbers::pi / 180)) /
                   (std::cos(20 * std::numbers::pi / 180) - std::cos(40 * std::numbers::pi / 180));
  EXPECT_NEAR(t * t, 0.3315081, 1e-6);
  EXPECT_GREY(front(at_angle_deg(30, 4), kFacingEye), t * t);
  EXPECT_GREY(front(at_angle_deg(10, 4), kFacingEye), 1.0);  // inside the inner cone
  EXPECT_GREY(front(at_angle_deg(50, 4), kFacingEye), 0.0);  // outside the outer cone
}

TEST_P(LightingCase, DualConeFalloffExponent) {
  material().ambient = Color3::Ones();
  Light l = smooth_spot(20, 40, 1);  // linear ramp (D3D9 falloff 1)
  l.ambient = Color3::Ones();
  scene.lights.push_back(l);
  const double t = (std::cos(std::numbers::pi / 6) - std::cos(40 * std::numbers::pi / 180)) /
                   (std::cos(20 * std::numbers::pi / 180) - std::cos(40 * std::numbers::pi / 180));
  EXPECT_GREY(front(at_angle_deg(30, 4), Vec3(0, 0, -1)), t);
}

TEST_P(LightingCase, RangeWindow) {
  material().diffuse = Color3::Ones();
  Light l = point_at(Vec3(0, 0, 2));  // d = 5 from kOrigin
  l.range = 10;
  scene.lights.push_back(l);
  // (1 - (5/10)^4)^2 = 0.9375^2 = 0.87890625
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.87890625);
  scene.lights[0].range = 5;  // at the range: nothing
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);
  scene.lights[0].range = 4;  // beyond it: nothing
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);
}

// Seed 003's linear range: clamp((max - d + min) / max, 0, 1), d = 5 here.
TEST_P(LightingCase, LinearRangeAttenuation) {
  material().diffuse = Color3::Ones();
  Light l = point_at(Vec3(0, 0, 2));
  l.attenuation_model = AttenuationModel::linear_range;
  l.range_min = 1, l.range_max = 8;
  scene.lights.push_back(l);
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.5);  // (8 - 5 + 1) / 8
  scene.lights[0].range_min = 6, scene.lights[0].range_max = 10;  // 1.1: clamped
  EXPECT_GREY(front(kOrigin, kFacingEye), 1.0);
  scene.lights[0].range_min = 3, scene.lights[0].range_max = 3;  // min = max: (3 - 5 + 3) / 3
  EXPECT_GREY(front(kOrigin, kFacingEye), 1.0 / 3.0);
  scene.lights[0].range_min = 1, scene.lights[0].range_max = 4;  // d = max + min: nothing
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);
  scene.lights[0].range_min = 0, scene.lights[0].range_max = 2;  // beyond: nothing, not negative
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);
  scene.lights[0].constant_attenuation = 100;  // GL's coefficients are not read
  scene.lights[0].range_min = 1, scene.lights[0].range_max = 8;
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.5);
}

// Phong's lobe: R = 2 (n.L) n - L mirrors L = unit(0, 1, 1) about n = z to unit(0, -1, 1), 45
// degrees from V = z, so (R.V)^10 = 2^-5, where Blinn's half vector (22.5 degrees) gives 0.453.
TEST_P(LightingCase, PhongLobeOnReflectionAndView) {
  material().specular = Color3(1.0f, 0.5f, 0.25f);
  material().shininess = 10;
  material().specular_model = SpecularModel::phong;
  scene.viewer = ViewerMode::infinite;
  scene.lights.push_back(directional_towards(Vec3(0, 1, 1)));
  EXPECT_COLOR(front(kOrigin, kFacingEye), 1.0 / 32, 0.5 / 32, 0.25 / 32);
}

// R.V < 0 on the lit side (a local viewer on the light's side of a grazing light) counts as 0:
// no highlight at shininess 10, and 0^0 = 1 at shininess 0, as Blinn's lobe gives.
TEST_P(LightingCase, PhongLobeNegativeReflectionCountsAsZero) {
  material().specular = Color3::Ones();
  material().diffuse = Color3::Zero();
  material().specular_model = SpecularModel::phong;
  material().shininess = 10;
  scene.viewer = ViewerMode::local;
  scene.lights.push_back(directional_towards(Vec3(-1, 0, 0.1f)));
  // V = (3, 0, -4): unit(V -> eye) = (-0.6, 0, 0.8); R = (0.995, 0, 0.0995): R.V = -0.517.
  EXPECT_GREY(front(Vec3(3, 0, -4), kFacingEye), 0.0);
  material().shininess = 0;
  EXPECT_GREY(front(Vec3(3, 0, -4), kFacingEye), 1.0);
}

TEST_P(LightingCase, DisabledLightContributesNothing) {
  material().diffuse = Color3::Ones();
  material().ambient = Color3::Ones();
  Light l = directional_towards(Vec3(0, 0, 1));
  l.ambient = Color3::Ones();
  l.enabled = false;
  scene.lights.push_back(l);
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.0);
}

TEST_P(LightingCase, BackFacingNormalWithoutTwoSided) {
  material().diffuse = Color3::Ones();
  material().ambient = Color3(0.5f, 0.5f, 0.5f);
  scene.global_ambient = Color3(0.2f, 0.2f, 0.2f);
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  const VertexColors c = light(kOrigin, Vec3(0, 0, -1));
  EXPECT_GREY(c.front[0], 0.1);  // only a_m a_scene
  EXPECT_TRUE(c.back.empty());
}

TEST_P(LightingCase, BackFacingNormalWithTwoSided) {
  material().diffuse = Color3::Ones();
  material().ambient = Color3(0.5f, 0.5f, 0.5f);
  scene.global_ambient = Color3(0.2f, 0.2f, 0.2f);
  scene.two_sided = true;
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  const VertexColors c = light(kOrigin, Vec3(0, 0, -1));
  ASSERT_EQ(c.back.size(), 1u);
  EXPECT_GREY(c.front[0], 0.1);  // the front side still faces away
  EXPECT_GREY(c.back[0], 1.0);   // the back side is lit with -n: 0.1 + 1, clamped to 1
  material().diffuse = Color3(0.5f, 0.5f, 0.5f);
  EXPECT_GREY(light(kOrigin, Vec3(0, 0, -1)).back[0], 0.6);
}

TEST_P(LightingCase, OverBrightSumIsClamped) {
  material().diffuse = Color3::Ones();
  Light l = directional_towards(Vec3(0, 0, 1));
  l.diffuse = Color3(0.8f, 0.3f, 0.8f);
  scene.lights.push_back(l);
  scene.lights.push_back(l);
  EXPECT_COLOR(front(kOrigin, kFacingEye), 1.0, 0.6, 1.0);
  EXPECT_COLOR(front(kOrigin, kFacingEye, /*clamp=*/false), 1.6, 0.6, 1.6);  // HDR keeps the sum
}

TEST_P(LightingCase, LightAtTheVertexStaysFinite) {
  material().ambient = Color3(0.5f, 0.5f, 0.5f);
  material().diffuse = material().specular = Color3::Ones();
  material().shininess = 8;
  Light l = point_at(kOrigin);
  l.ambient = Color3(0.2f, 0.2f, 0.2f);
  scene.lights.push_back(l);
  // VP has no direction: no diffuse or specular; ambient a_m a_i att = 0.1 with att = 1.
  EXPECT_GREY(front(kOrigin, kFacingEye), 0.1);
  // k0 = 0: the denominator is floored at 1e-6, so att = 1e6 and the ambient saturates.
  scene.lights[0].constant_attenuation = 0;
  scene.lights[0].linear_attenuation = 1;
  EXPECT_GREY(front(kOrigin, kFacingEye), 1.0);
  EXPECT_GREY(front(kOrigin, kFacingEye, false), 1e5);  // 0.5 * 0.2 * 1e6
}

TEST_P(LightingCase, ZeroNormalGetsOnlyAmbient) {
  material().ambient = Color3(0.5f, 0.5f, 0.5f);
  material().diffuse = material().specular = Color3::Ones();
  scene.global_ambient = Color3(0.2f, 0.2f, 0.2f);
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  EXPECT_GREY(front(kOrigin, Vec3::Zero()), 0.1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_GREY(front(kOrigin, Vec3(nan, 0, 1)), 0.1);  // a NaN normal counts as zero
  EXPECT_GREY(front(kOrigin, Vec3(1e-9f, 0, 0)), 0.1);  // shorter than 1e-6: no direction
}

TEST_P(LightingCase, NaNPositionDropsPositionalLightsOnly) {
  material().diffuse = Color3::Ones();
  material().emissive = Color3(0.1f, 0.1f, 0.1f);
  scene.lights.push_back(point_at(Vec3(0, 0, 5)));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_GREY(front(Vec3(nan, 0, -3), kFacingEye), 0.1);
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  Light& d = scene.lights.back();
  d.diffuse = Color3(0.5f, 0.5f, 0.5f);
  EXPECT_GREY(front(Vec3(nan, 0, -3), kFacingEye), 0.6);
}

TEST_P(LightingCase, LightOppositeTheEyeGivesZeroHalfVector) {
  material().diffuse = Color3(0.5f, 0.5f, 0.5f);
  material().specular = Color3::Ones();
  material().shininess = 10;
  scene.viewer = ViewerMode::local;
  scene.lights.push_back(point_at(Vec3(0, 0, -10)));
  // V = (0,0,-5): VP = (0,0,-1) = -unit(V->eye), so h = 0 and n.h = 0: diffuse only.
  EXPECT_GREY(front(Vec3(0, 0, -5), Vec3(0, 0, -1)), 0.5);
  scene.viewer = ViewerMode::infinite;  // the same with the infinite viewer and a directional light
  scene.lights[0] = directional_towards(Vec3(0, 0, -1));
  EXPECT_GREY(front(Vec3(0, 0, -5), Vec3(0, 0, -1)), 0.5);
}

TEST_P(LightingCase, LightsAddUp) {
  material().diffuse = Color3::Ones();
  Light a = directional_towards(Vec3(0, 0, 1));
  a.diffuse = Color3(0.25f, 0, 0);
  Light b = point_at(Vec3(3, 0, 1));  // n.VP = 0.8 (see PointLightDirection)
  b.diffuse = Color3(0, 0.5f, 0.5f);
  scene.lights = {a, b};
  EXPECT_COLOR(front(kOrigin, kFacingEye), 0.25, 0.4, 0.4);
}

TEST_P(LightingCase, CameraAndModelTransformsLeaveEyeSpaceValuesUnchanged) {
  material().diffuse = Color3::Ones();
  // PointLightDirection's set-up moved as a whole: camera at (10, 2, 0) looking along -x, the
  // vertex put there by a model translation. In eye space nothing changes: 0.8.
  scene.camera.eye = Vec3(10, 2, 0);
  scene.camera.target = Vec3(9, 2, 0);
  // The eye's axes in world space: right = (0,0,-1), up = (0,1,0), back = (1,0,0). So vertex
  // eye (0,0,-3) -> world (7,2,0); light eye (3,0,1) -> world (11,2,-3); normal eye z -> world +x.
  scene.lights.push_back(point_at(Vec3(11, 2, -3)));
  set_single_vertex(scene, Vec3::Zero(), Vec3(1, 0, 0));
  scene.objects[0].model.block<3, 1>(0, 3) = Vec3(7, 2, 0);
  const LightingOptions options = options_for_path();
  VertexColors out;
  ASSERT_TRUE(light_instance(scene, 0, options, out).ok());
  EXPECT_GREY(out.front[0], 0.8);
}

TEST_P(LightingCase, NonUniformScaleTransformsNormalsByInverseTranspose) {
  material().diffuse = Color3::Ones();
  scene.lights.push_back(directional_towards(Vec3(0, 0, 1)));
  set_single_vertex(scene, kOrigin, Vec3(0, static_cast<float>(kInvSqrt2), static_cast<float>(kInvSqrt2)));
  scene.objects[0].model(1, 1) = 2;  // stretch y: the surface tilts towards z
  // The normal of the scaled surface is ~ (0, 1/2, 1): n.z = 1/sqrt(1.25) = 0.89442719. (Scaling
  // the normal like a position would give (0, 2, 1)/sqrt 5, n.z = 0.447.)
  const LightingOptions options = options_for_path();
  VertexColors out;
  ASSERT_TRUE(light_instance(scene, 0, options, out).ok());
  EXPECT_GREY(out.front[0], 1.0 / std::sqrt(1.25));
}

TEST_P(LightingCase, InvalidSceneIsRejectedAndOutputUntouched) {
  set_single_vertex(scene, kOrigin, kFacingEye);
  scene.materials[0].shininess = -1;
  const LightingOptions options = options_for_path();
  VertexColors out;
  out.front = {Color3(7, 7, 7)};
  const Status s = light_instance(scene, 0, options, out);
  EXPECT_EQ(s.code(), ErrorCode::invalid_argument);
  EXPECT_EQ(s.field(), "materials[0].shininess");
  EXPECT_EQ(out.front[0], Color3(7, 7, 7));
  EXPECT_EQ(light_instance(scene, 5, options, out).field(), "instance");
}

INSTANTIATE_TEST_SUITE_P(Paths, LightingCase,
                         ::testing::Values(PathCase{LightingPath::reference, Isa::best},
                                           PathCase{LightingPath::scalar, Isa::best},
                                           PathCase{LightingPath::simd, Isa::sse2}, PathCase{LightingPath::simd, Isa::avx2},
                                           PathCase{LightingPath::simd, Isa::avx512},
                                           PathCase{LightingPath::simd, Isa::sse2, PowTier::automatic},
                                           PathCase{LightingPath::simd, Isa::avx2, PowTier::automatic},
                                           PathCase{LightingPath::simd, Isa::avx512, PowTier::automatic},
                                           PathCase{LightingPath::simd, Isa::sse2, PowTier::fast},
                                           PathCase{LightingPath::simd, Isa::avx2, PowTier::fast},
                                           PathCase{LightingPath::simd, Isa::avx512, PowTier::fast}),
                         [](const auto& param_info) { return name_of(param_info.param); });

}  // namespace
}  // namespace facet
