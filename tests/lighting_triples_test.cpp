// The SIMD lighting kernel reading a mesh's xyz triples itself (positions, normals, vertex colours)
// and writing its colours as triples, against the same kernel on its structure-of-arrays copies
// (the path the frame's indexed vertices take): the same bytes on every ISA and tier, for every
// tail length and start, both sides, with colour material and separate specular. And the frame's
// choice between them per chunk of vertices (frame::kLightWholeChunk).
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/look_at.hpp"
#include "facet/facet.hpp"
#include "lighting/point_shader.hpp"
#include "render_support.hpp"
#include "test_support.hpp"

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

// Three chunks of 1024 vertices (32 x 32 grids side by side, facing the camera): the first draws
// the cells of its first 10 rows (320 vertices: lit through their list), the second those of its
// first 20 rows (640, more than half: the whole chunk is lit in place), the third faces away
// (culled, nothing lit). The counts say which way each chunk went; the picture is the one with
// every vertex lit, on every path.
TEST(LightingTriples, FrameLightsAMostlyDrawnChunkWholeAndTheRestThroughTheirList) {
  Scene s;
  Mesh grid;
  const std::uint32_t side = 32;
  for (std::uint32_t c = 0; c < 3; ++c) {
    const std::uint32_t first = c * side * side;
    for (std::uint32_t j = 0; j < side; ++j) {
      for (std::uint32_t i = 0; i < side; ++i) {
        grid.positions.emplace_back(-2.5f + 0.05f * static_cast<float>(i) + 1.7f * static_cast<float>(c),
                                    -0.8f + 0.05f * static_cast<float>(j), -6.0f);
        grid.normals.emplace_back(0.1f * static_cast<float>(c), 0.02f * static_cast<float>(j % 5), 1.0f);
      }
    }
    const std::uint32_t rows = c == 0 ? 9 : c == 1 ? 19 : side - 1;  // cells: rows + 1 rows of vertices
    for (std::uint32_t j = 0; j < rows; ++j) {
      for (std::uint32_t i = 0; i + 1 < side; ++i) {
        const std::uint32_t a = first + j * side + i, b = a + 1, d = a + side, e = d + 1;
        if (c == 2) {  // facing away
          grid.triangles.push_back({a, d, b});
          grid.triangles.push_back({b, d, e});
        } else {
          grid.triangles.push_back({a, b, d});
          grid.triangles.push_back({b, e, d});
        }
      }
    }
  }
  s.meshes.push_back({"grids", grid});
  Material m;
  m.diffuse = {0.7f, 0.5f, 0.3f};
  m.specular = {0.4f, 0.4f, 0.4f};
  m.shininess = 20.0f;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  Light point;
  point.type = LightType::point;
  point.position = Vec3(0.0f, 0.5f, -3.0f);
  s.lights.push_back(point);
  s.camera.eye = Vec3(0.0f, 0.0f, 0.0f);
  s.camera.target = Vec3(0.0f, 0.0f, -1.0f);
  for (const auto& [path, isa] : std::vector<std::pair<LightingPath, Isa>>{
           {LightingPath::scalar, Isa::best}, {LightingPath::simd, Isa::sse2}, {LightingPath::simd, Isa::best}}) {
    RenderOptions o = test::gl_options();
    o.path = path;
    o.isa = isa;
    o.threads = 2;
    test::Canvas listed(400, 300), every(400, 300);  // cells of 3 pixels: none is too small to draw
    FrameStats a, b;
    Renderer r;
    ASSERT_TRUE(r.render(s, o, listed.view(), nullptr, &a).ok());
    o.light_every_vertex = true;
    ASSERT_TRUE(r.render(s, o, every.view(), nullptr, &b).ok());
    EXPECT_TRUE(listed.pixels() == every.pixels()) << to_string(path) << " " << to_string(isa);
    EXPECT_EQ(a.triangles_culled, 2u * 31u * 31u) << a.triangles_drawn << " " << a.triangles_small << " " << a.triangles_outside << " " << a.triangles_clipped;
    EXPECT_EQ(a.vertices_lit, 320u + 1024u) << to_string(path);
    EXPECT_EQ(a.vertices_skipped, 3u * 1024u - 1344u);
    EXPECT_EQ(b.vertices_lit, 3u * 1024u);
  }
}

}  // namespace
}  // namespace facet
