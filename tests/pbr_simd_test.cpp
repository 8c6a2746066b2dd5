// The SIMD PBR kernel (lighting/shade_pbr_simd.hpp) against its scalar twin, shade_pbr<float>,
// on every ISA this machine has and both tiers (the estimates; IEEE sqrt and division): random
// eye-space points, normals (a zero and a NaN one among them) and materials under a directional,
// a point and a spot light, with the studio and with a picture turned and scaled, per-point
// metallic-roughness texels, albedo, occlusion and separate specular; and a mesh's vertices read
// as triples through a model matrix (light_mesh). Prints the measured worst difference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/look_at.hpp"
#include "facet/facet.hpp"
#include "lighting/image_light.hpp"
#include "lighting/point_shader.hpp"

namespace facet {
namespace {

const auto kInTurn = [](std::size_t n, const std::function<void(std::size_t)>& fn) {
  for (std::size_t i = 0; i < n; ++i) fn(i);
};

// A sky with detail at every scale (bands, a sun, a dark ground), so that every level of the
// prefiltered cube differs from its neighbours.
EnvironmentLight busy_sky() {
  EnvironmentLight e;
  e.source = EnvironmentSource::image;
  e.width = 128, e.height = 64;
  e.rgb.resize(128 * 64 * 3);
  for (int r = 0; r < 64; ++r) {
    for (int c = 0; c < 128; ++c) {
      float* t = &e.rgb[3 * (std::size_t(r) * 128 + std::size_t(c))];
      const float band = (c / 8) % 2 ? 0.9f : 0.3f, up = r < 32 ? 1.0f : 0.1f;
      const float sun = (std::abs(c - 40) < 3 && std::abs(r - 14) < 3) ? 30.0f : 0.0f;
      t[0] = up * band + sun, t[1] = up * 0.7f + 0.5f * sun, t[2] = up * (1.2f - band) + 0.2f * sun;
    }
  }
  e.intensity = 0.8f;
  e.rotation_deg = 35.0f;
  return e;
}

Scene lit_scene(EnvironmentSource source) {
  Scene s;
  s.camera.eye = Vec3(0.0f, 0.0f, 0.0f);
  s.camera.target = Vec3(0.3f, -0.2f, -1.0f);
  Light sun;  // directional
  sun.direction = Vec3(-0.3f, -1.0f, -0.6f).normalized();
  sun.diffuse = Color3(0.8f, 0.7f, 0.6f);
  sun.ambient = Color3(0.05f, 0.05f, 0.06f);
  s.lights.push_back(sun);
  Light point;
  point.type = LightType::point;
  point.position = Vec3(1.0f, 2.0f, -3.0f);
  point.diffuse = Color3(0.9f, 0.3f, 0.2f);
  point.linear_attenuation = 0.2f;
  point.range = 9.0f;
  s.lights.push_back(point);
  Light spot;
  spot.type = LightType::spot;
  spot.position = Vec3(-2.0f, 1.0f, -1.0f);
  spot.direction = Vec3(0.4f, -0.3f, -0.8f).normalized();
  spot.spot_shape = SpotShape::smooth_cone;
  spot.spot_outer_deg = 50.0f;
  spot.spot_inner_deg = 20.0f;
  spot.diffuse = Color3(0.2f, 0.5f, 1.0f);
  s.lights.push_back(spot);
  s.global_ambient = Color3(0.1f, 0.12f, 0.15f);
  if (source == EnvironmentSource::image) s.environment_light = busy_sky();
  s.environment_light.source = source;
  return s;
}

Material random_material(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Material m;
  m.model = MaterialModel::pbr;
  m.base_color = Color3(u(rng), u(rng), u(rng));
  m.metallic = u(rng) < 0.3f ? 0.0f : (u(rng) < 0.4f ? 1.0f : u(rng));
  m.roughness = u(rng);
  m.ior = 1.0f + 1.5f * u(rng);
  m.specular_weight = 0.5f + 0.5f * u(rng);
  m.specular_color = Color3(0.8f + 0.2f * u(rng), 1.0f, 0.9f);
  m.emissive = u(rng) < 0.2f ? Color3(0.1f, 0.05f, 0.0f) : Color3::Zero();
  return m;
}

struct Points {
  std::vector<Vec3> p, n;
  std::vector<Color3> albedo;
  std::vector<float> occlusion, metal_rough;  // metallic at [i], roughness at [count + i]
};

Points random_points(std::size_t count, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  Points pts;
  for (std::size_t i = 0; i < count; ++i) {
    pts.p.emplace_back(3.0f * u(rng), 3.0f * u(rng), -4.0f + 2.0f * u(rng));
    pts.n.emplace_back(u(rng), u(rng), u(rng));
    pts.albedo.emplace_back(w(rng), w(rng), w(rng));
    pts.occlusion.push_back(w(rng));
  }
  pts.metal_rough.resize(2 * count);
  for (float& t : pts.metal_rough) t = w(rng);
  pts.n[3] = Vec3::Zero();                                              // no normal: the emission
  pts.n[7] = Vec3(std::numeric_limits<float>::quiet_NaN(), 0.0f, 1.0f);  // NaN: likewise
  pts.metal_rough[5] = std::numeric_limits<float>::quiet_NaN();          // a NaN texel
  return pts;
}

std::vector<Isa> isas() {
  std::vector<Isa> out;
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) out.push_back(isa);
  return out;
}

// |a - b| / max(1, |b|) per channel, the worst over both outputs.
struct Worst {
  double value = 0.0;
  std::string where;
  void add(const Color3& a, const Color3& b, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
      const double e = std::abs(double(a[c]) - double(b[c])) / std::max(1.0, std::abs(double(b[c])));
      if (!(e <= value)) value = std::isnan(e) ? 1e9 : e, where = what;
    }
  }
};

// The twin bound: float rounding of terms near 1 (the estimates' 2^-22 times the few dozen
// operations that carry them), and no more.
constexpr double kTwinBound = 2e-5;

TEST(PbrSimd, TheKernelIsItsScalarTwinOnEveryIsaAndTier) {
  std::mt19937 rng(2026);
  const std::size_t count = 333;  // a padded tail on every ISA
  Points pts = random_points(count, rng);
  Worst worst;
  int compared = 0;
  for (EnvironmentSource source : {EnvironmentSource::studio, EnvironmentSource::image, EnvironmentSource::none}) {
    const Scene scene = lit_scene(source);
    lighting::ImageLight light;
    ASSERT_TRUE(light.build(scene.environment_light, kInTurn).ok());
    const Eigen::Matrix4d view = look_at_d(scene.camera);
    for (int k = 0; k < 6; ++k) {
      const Material m = random_material(rng);
      for (int variant = 0; variant < 4; ++variant) {
        lighting::LightingFeatures f;
        f.image_light = &light;
        f.metal_rough = variant & 1;
        f.color_material = variant & 2;
        f.occlusion = variant == 3;
        f.separate_specular = variant >= 2;
        LightingOptions scalar_options;
        scalar_options.path = LightingPath::scalar;
        scalar_options.clamp = variant != 1;
        lighting::PointShader scalar;
        ASSERT_TRUE(scalar.prepare(scene, view, m, scalar_options, nullptr, f).ok());
        lighting::SoaScratch scratch;
        std::vector<Color3> want(count), want_spec(count);
        scalar.shade_points(count, pts.p.data(), pts.n.data(), want.data(), scratch, pts.albedo.data(), want_spec.data(),
                            pts.occlusion.data(), pts.metal_rough.data());
        for (Isa isa : isas()) {
          for (PowTier tier : {PowTier::automatic, PowTier::exact}) {
            LightingOptions o = scalar_options;
            o.path = LightingPath::simd, o.isa = isa, o.pow_tier = tier;
            lighting::PointShader simd;
            ASSERT_TRUE(simd.prepare(scene, view, m, o, nullptr, f).ok());
            std::vector<Color3> got(count), got_spec(count);
            simd.shade_points(count, pts.p.data(), pts.n.data(), got.data(), scratch, pts.albedo.data(), got_spec.data(),
                              pts.occlusion.data(), pts.metal_rough.data());
            for (std::size_t i = 0; i < count; ++i) {
              const std::string what = std::string(to_string(source)) + " material " + std::to_string(k) + " variant " +
                                       std::to_string(variant) + " " + to_string(isa) + " " + to_string(tier) + " point " +
                                       std::to_string(i);
              worst.add(got[i], want[i], what);
              if (f.separate_specular) worst.add(got_spec[i], want_spec[i], what + " (specular)");
            }
            // No normal: the emission alone, exactly.
            for (std::size_t i : {std::size_t(3), std::size_t(7)}) EXPECT_EQ(got[i], m.emissive) << i;
            ++compared;
          }
        }
      }
    }
  }
  std::printf("SIMD PBR vs its scalar twin: worst relative difference %.3g (%s), %d comparisons\n", worst.value,
              worst.where.c_str(), compared);
  EXPECT_GT(compared, 0);
  EXPECT_LE(worst.value, kTwinBound) << worst.where;
}

TEST(PbrSimd, AMeshsTriplesAreLitAsTheScalarTwinLightsThem) {
  std::mt19937 rng(11);
  const std::size_t count = 101;
  Points pts = random_points(count, rng);
  Scene scene = lit_scene(EnvironmentSource::studio);
  Mesh mesh;
  mesh.positions = pts.p, mesh.normals = pts.n, mesh.colors = pts.albedo;
  Mat4 model = Mat4::Identity();
  model.block<3, 3>(0, 0) = Eigen::AngleAxisf(0.7f, Vec3(1, -2, 1).normalized()).toRotationMatrix() * 0.8f;
  model(2, 3) = -1.0f;
  lighting::ImageLight light;
  ASSERT_TRUE(light.build(scene.environment_light, kInTurn).ok());
  const Eigen::Matrix4d view = look_at_d(scene.camera);
  lighting::LightingFeatures f;
  f.image_light = &light;
  f.color_material = true;
  const Material m = random_material(rng);
  LightingOptions so;
  so.path = LightingPath::scalar;
  lighting::PointShader scalar;
  ASSERT_TRUE(scalar.prepare(scene, view, m, so, nullptr, f).ok());
  lighting::SoaScratch scratch;
  Worst worst;
  for (bool back : {false, true}) {
    std::vector<Color3> want(count);
    scalar.light_mesh(mesh, view, model, back, 0, count, want.data(), scratch);
    for (Isa isa : isas()) {
      LightingOptions o = so;
      o.path = LightingPath::simd, o.isa = isa;
      lighting::PointShader simd;
      ASSERT_TRUE(simd.prepare(scene, view, m, o, nullptr, f).ok());
      std::vector<Color3> got(count);
      simd.light_mesh(mesh, view, model, back, 0, count, got.data(), scratch);
      for (std::size_t i = 0; i < count; ++i)
        worst.add(got[i], want[i], std::string(to_string(isa)) + (back ? " back" : " front") + " vertex " + std::to_string(i));
    }
  }
  std::printf("SIMD PBR on triples vs its scalar twin: worst relative difference %.3g (%s)\n", worst.value, worst.where.c_str());
  EXPECT_LE(worst.value, kTwinBound) << worst.where;
}

}  // namespace
}  // namespace facet
