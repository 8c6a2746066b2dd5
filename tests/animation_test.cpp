// glTF animation samplers (scene/animation.hpp) against closed forms: a node turning 90 degrees
// about +Y under STEP, LINEAR (slerp: exact angles) and CUBICSPLINE (Hermite with the tangents
// scaled by the keys' interval), times before the first and after the last key, the shortest arc,
// weights, and bad tracks refused by name.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "scene/animation.hpp"

namespace facet::animation {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A quaternion turning by `deg` about +Y, as glTF stores it (x, y, z, w).
std::vector<float> about_y(double deg) {
  return {0.0f, float(std::sin(0.5 * deg * kDeg)), 0.0f, float(std::cos(0.5 * deg * kDeg))};
}

// The angle about +Y of a unit quaternion with no x or z part.
double angle_of(const float* q) { return 2.0 * std::atan2(double(q[1]), double(q[3])) / kDeg; }

Track turn(Interpolation how, double from_deg, double to_deg, float t0 = 0.0f, float t1 = 1.0f) {
  Track t;
  t.interpolation = how;
  t.components = 4;
  t.rotation = true;
  t.times = {t0, t1};
  const std::vector<float> a = about_y(from_deg), b = about_y(to_deg);
  if (how == Interpolation::cubic_spline) {
    const std::vector<float> zero(4, 0.0f);
    for (const auto* part : {&zero, &a, &zero, &zero, &b, &zero}) t.values.insert(t.values.end(), part->begin(), part->end());
  } else {
    t.values = a;
    t.values.insert(t.values.end(), b.begin(), b.end());
  }
  return t;
}

TEST(Animation, LinearRotationIsSlerpAtExactAngles) {
  const Track t = turn(Interpolation::linear, 0.0, 90.0);
  ASSERT_TRUE(validate_track(t, "animations[0].samplers[0]").ok());
  float q[4];
  for (const double s : {0.0, 0.25, 0.5, 0.8, 1.0}) {
    sample(t, s, q);
    EXPECT_NEAR(angle_of(q), 90.0 * s, 1e-4) << s;
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-6);
  }
  // Before the first key and after the last: clamped.
  sample(t, -3.0, q);
  EXPECT_NEAR(angle_of(q), 0.0, 1e-5);
  sample(t, 7.0, q);
  EXPECT_NEAR(angle_of(q), 90.0, 1e-4);
}

TEST(Animation, TheShortestArcIsTaken) {
  // 170 to 190 degrees (stored as -170): the short way through 180, not back through 0.
  Track t = turn(Interpolation::linear, 170.0, 190.0);
  float q[4];
  sample(t, 0.5, q);
  const double a = std::fmod(angle_of(q) + 360.0, 360.0);
  EXPECT_NEAR(a, 180.0, 1e-3);
  // The second key negated (the same rotation): still the short way.
  for (int i = 4; i < 8; ++i) t.values[std::size_t(i)] = -t.values[std::size_t(i)];
  sample(t, 0.5, q);
  EXPECT_NEAR(std::fmod(angle_of(q) + 360.0, 360.0), 180.0, 1e-3);
}

TEST(Animation, StepHoldsEachKeyUntilTheNext) {
  const Track t = turn(Interpolation::step, 0.0, 90.0, 1.0f, 2.0f);
  float q[4];
  sample(t, 1.0, q);
  EXPECT_NEAR(angle_of(q), 0.0, 1e-5);
  sample(t, 1.999, q);
  EXPECT_NEAR(angle_of(q), 0.0, 1e-5);
  sample(t, 2.0, q);
  EXPECT_NEAR(angle_of(q), 90.0, 1e-4);
}

TEST(Animation, CubicSplineIsHermiteWithTangentsScaledByTheInterval) {
  // Zero tangents: smoothstep between the keys, 3 s^2 - 2 s^3 of the way.
  const Track r = turn(Interpolation::cubic_spline, 0.0, 90.0);
  float q[4];
  sample(r, 0.5, q);
  // Halfway in each component, renormalised: 45 degrees exactly (a symmetric blend).
  EXPECT_NEAR(angle_of(q), 45.0, 1e-4);
  // A translation along x from 0 to 1 over keys 2 s apart, out-tangent 3 at the first key and
  // in-tangent -1 at the second: p(s) = 2 (s^3 - 2 s^2 + s) 3 + (3 s^2 - 2 s^3) + 2 (s^3 - s^2) (-1).
  Track x;
  x.interpolation = Interpolation::cubic_spline;
  x.components = 1;
  x.times = {1.0f, 3.0f};
  x.values = {0.0f, 0.0f, 3.0f, -1.0f, 1.0f, 0.0f};
  ASSERT_TRUE(validate_track(x, "x").ok());
  for (const double s : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    float v;
    sample(x, 1.0 + 2.0 * s, &v);
    const double want = 2 * (s * s * s - 2 * s * s + s) * 3 + (3 * s * s - 2 * s * s * s) + 2 * (s * s * s - s * s) * -1;
    EXPECT_NEAR(v, want, 1e-6) << s;
  }
}

TEST(Animation, WeightsBlendLinearly) {
  Track w;
  w.components = 2;
  w.times = {0.0f, 0.5f, 1.0f};
  w.values = {0.0f, 1.0f, 1.0f, 0.0f, 0.5f, 0.5f};
  float v[2];
  sample(w, 0.25, v);
  EXPECT_FLOAT_EQ(v[0], 0.5f);
  EXPECT_FLOAT_EQ(v[1], 0.5f);
  sample(w, 0.75, v);
  EXPECT_FLOAT_EQ(v[0], 0.75f);
  EXPECT_FLOAT_EQ(v[1], 0.25f);
}

TEST(Animation, BadTracksAreRefusedByName) {
  const std::string where = "animations[1].samplers[0]";
  Track t = turn(Interpolation::linear, 0.0, 90.0);
  t.times = {1.0f, 1.0f};
  Status st = validate_track(t, where);
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(st.field(), where + ".input");
  t.times = {0.0f, std::nanf("")};
  EXPECT_EQ(validate_track(t, where).field(), where + ".input");
  t.times = {0.0f, 1.0f};
  t.values[5] = std::nanf("");
  EXPECT_EQ(validate_track(t, where).field(), where + ".output");
  t.values.pop_back();
  st = validate_track(t, where);
  EXPECT_EQ(st.field(), where + ".output");
  EXPECT_NE(st.message().find("expected 8"), std::string::npos) << st.message();
  t.times.clear();
  EXPECT_EQ(validate_track(t, where).field(), where + ".input");
  Track r = turn(Interpolation::linear, 0.0, 90.0);
  r.components = 3;
  EXPECT_EQ(validate_track(r, where).field(), where + ".output");
}

}  // namespace
}  // namespace facet::animation
