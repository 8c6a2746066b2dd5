// The SIMD lighting kernel reading a mesh's xyz triples itself (positions, normals, vertex colours)
// and writing its colours as triples, against the same kernel on its structure-of-arrays copies
// (the path the frame's indexed vertices take): the same bytes on every ISA and tier, for every
// tail length and start, both sides, with colour material and separate specular.
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/look_at.hpp"
#include "facet/facet.hpp"
#include "lighting/point_shader.hpp"

namespace facet {
namespace {

Scene triples_scene(std::size_t n, bool colours) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Mesh mesh;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng);
    mesh.positions.emplace_back(3.0f * x, 3.0f * y, 3.0f * z - 1.0f);
    const float a = u(rng), b = u(rng), c = u(rng);
    mesh.normals.emplace_back(a, b, c);
    if (colours) {
      const float r = u(rng), g = u(rng), bl = u(rng);
      mesh.colors.emplace_back(0.5f + 0.5f * r, 0.5f + 0.5f * g, 0.5f + 0.5f * bl);
    }
  }
  if (n > 0) mesh.normals[n / 2] = Vec3(0.0f, 0.0f, 0.0f);  // no normal: black but for ambient
  Scene scene;
  scene.meshes.push_back({"cloud", mesh});
  Material m;
  m.diffuse = {0.8f, 0.6f, 0.4f};
  m.specular = {0.5f, 0.5f, 0.5f};
  m.shininess = 37.0f;
  scene.materials.push_back(m);
  Mat4 model = Mat4::Identity();
  model.block<3, 3>(0, 0) = Eigen::AngleAxisf(0.4f, Vec3(1, 2, 3).normalized()).toRotationMatrix() * 1.5f;
  model(0, 3) = 0.25f;
  scene.objects.push_back({0, 0, model});
  Light point;
  point.type = LightType::point;
  point.position = Vec3(2.0f, 1.0f, 4.0f);
  point.linear_attenuation = 0.1f;
  scene.lights.push_back(point);
  Light spot;
  spot.type = LightType::spot;
  spot.position = Vec3(-3.0f, 2.0f, 3.0f);
  spot.direction = Vec3(0.6f, -0.4f, -0.7f).normalized();
  spot.spot_cutoff_deg = 40.0f;
  spot.spot_exponent = 6.0f;
  scene.lights.push_back(spot);
  Light sun;  // default: directional
  scene.lights.push_back(sun);
  scene.camera.eye = Vec3(0.5f, 1.0f, 8.0f);
  scene.camera.target = Vec3(0.0f, 0.0f, 0.0f);
  return scene;
}

TEST(LightingTriples, KernelOnTriplesGivesTheBytesOfItsStreams) {
  const std::size_t n = 100;
  std::vector<Isa> isas;
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) isas.push_back(isa);
  int compared = 0;
  for (bool colours : {false, true}) {
    const Scene scene = triples_scene(n, colours);
    const Eigen::Matrix4d view = look_at_d(scene.camera);
    const Mesh& mesh = scene.meshes[0].mesh;
    std::vector<std::uint32_t> identity(n);
    for (std::size_t i = 0; i < n; ++i) identity[i] = static_cast<std::uint32_t>(i);
    for (Isa isa : isas) {
      for (PowTier tier : {PowTier::automatic, PowTier::exact, PowTier::fast}) {
        for (bool split : {false, true}) {
          LightingOptions o;
          o.path = LightingPath::simd;
          o.isa = isa;
          o.pow_tier = tier;
          lighting::LightingFeatures features;
          features.color_material = colours;
          features.separate_specular = split;
          lighting::PointShader shader;
          ASSERT_TRUE(shader.prepare(scene, view, scene.materials[0], o, nullptr, features).ok());
          lighting::SoaScratch scratch;
          // Every start and tail length up to two avx512 batches and a bit, and the whole cloud.
          std::vector<std::pair<std::size_t, std::size_t>> ranges;
          for (std::size_t begin : {0u, 1u, 3u})
            for (std::size_t count = 0; count <= 37; ++count) ranges.push_back({begin, begin + count});
          ranges.push_back({0, n});
          for (bool back : {false, true}) {
            for (const auto& [begin, end] : ranges) {
              const Color3 unset(-7.0f, -7.0f, -7.0f);
              std::vector<Color3> a(n, unset), b(n, unset), sa(n, unset), sb(n, unset);
              shader.light_mesh(mesh, view, scene.objects[0].model, back, begin, end, a.data(), scratch,
                                split ? sa.data() : nullptr);
              shader.light_mesh(mesh, view, scene.objects[0].model, back, begin, end, b.data(), scratch,
                                split ? sb.data() : nullptr, identity.data());
              const std::string at = std::string(to_string(isa)) + " " + to_string(tier) + (colours ? " colours" : "") +
                                     (split ? " split" : "") + (back ? " back" : "") + " [" + std::to_string(begin) +
                                     ", " + std::to_string(end) + ")";
              ASSERT_EQ(std::memcmp(a.data(), b.data(), n * sizeof(Color3)), 0) << at;
              ASSERT_EQ(std::memcmp(sa.data(), sb.data(), n * sizeof(Color3)), 0) << at;
              for (std::size_t i = 0; i < n; ++i) {
                const bool inside = i >= begin && i < end;
                ASSERT_EQ(a[i] == unset, !inside) << at << ": vertex " << i;  // written exactly in the range
              }
              ++compared;
            }
          }
        }
      }
    }
  }
  EXPECT_GT(compared, 0);
}

}  // namespace
}  // namespace facet
