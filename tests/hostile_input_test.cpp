// Hostile input (the catalogue of the hardening work) that the other suites do not already cover:
// every case ends in a clear error or a correct picture, never a crash, a hang or a stray write.
#include <cstring>
#include <sstream>

#include "render_support.hpp"

namespace facet {
namespace {

TEST(HostileInput, SceneFileWithHundredThousandLights) {
  std::ostringstream json;
  json << "{\"meshes\": [{\"name\": \"b\", \"shape\": \"sphere\", \"segments\": 8, \"rings\": 4}],\n"
          " \"objects\": [{\"mesh\": \"b\"}],\n \"lights\": [\n";
  for (int i = 0; i < 100000; ++i) {
    json << (i ? ",\n" : "") << "{\"type\": \"point\", \"position\": [" << (i % 100) << ", " << (i / 100 % 100) << ", 50], "
         << "\"range\": 2}";
  }
  json << "]}";
  const Result<Scene> scene = parse_scene_json(json.str(), "many.json", "");
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  EXPECT_EQ(scene->lights.size(), 100000u);
  test::Canvas c(8, 8);
  FrameStats st;
  Renderer r;
  ASSERT_TRUE(r.render(*scene, {}, c.view(), nullptr, &st).ok());
  EXPECT_TRUE(c.outside_pixels_untouched());
  EXPECT_GT(st.vertex_lights_skipped, 0u) << "out-of-range lights are skipped by the frame plan";
}

Scene one_mesh(Mesh m) {
  Scene s = test::camera_scene();
  m.normals.assign(m.positions.size(), Vec3(0, 0, 1));
  s.meshes.push_back({"m", std::move(m)});
  s.materials.push_back(Material{});
  s.objects.push_back({0, 0, Mat4::Identity()});
  return s;
}

TEST(HostileInput, EmptyMesh) {
  test::Canvas c(8, 8);
  FrameStats st;
  Renderer r;
  ASSERT_TRUE(r.render(one_mesh(Mesh{}), {}, c.view(), nullptr, &st).ok());
  EXPECT_EQ(st.triangles_in, 0u);
  EXPECT_TRUE(c.outside_pixels_untouched());
}

TEST(HostileInput, TenMillionDegenerateTriangles) {
  Mesh m;
  m.positions = {Vec3(0, 0, -5), Vec3(1, 1, -5), Vec3(2, 2, -5)};  // collinear
  m.triangles.assign(10'000'000, {0, 1, 2});
  test::Canvas c(16, 16);
  FrameStats st;
  Renderer r;
  ASSERT_TRUE(r.render(one_mesh(std::move(m)), {}, c.view(), nullptr, &st).ok());
  EXPECT_EQ(st.triangles_in, 10'000'000u);
  EXPECT_EQ(st.triangles_drawn, 0u);
  EXPECT_EQ(st.pixels_filled, 0u);
}

TEST(HostileInput, EveryVertexAtTheSamePointAndTinyCoordinates) {
  for (float v : {0.0f, 1e-30f}) {
    Mesh m;
    for (int i = 0; i < 30; ++i) m.positions.push_back(Vec3(v * float(i % 3), v * float(i % 5), -5.0f));
    for (std::uint32_t i = 0; i + 2 < 30; ++i) m.triangles.push_back({i, i + 1, i + 2});
    test::Canvas c(16, 16);
    FrameStats st;
    Renderer r;
    ASSERT_TRUE(r.render(one_mesh(m), {}, c.view(), nullptr, &st).ok());
    EXPECT_EQ(st.pixels_filled, 0u);
    EXPECT_EQ(st.triangles_degenerate + st.triangles_culled + st.triangles_small, st.triangles_in);
  }
}

TEST(HostileInput, UnalignedFloatBuffer) {
  Scene s = test::camera_scene();
  test::add_quad(s, -30, -9, 30, 9, -5, Color3(0.25f, 0.5f, 1.0f));  // covers the 4:1 view
  // 16 x 4 RGBA32F pixels starting one byte into the buffer: any alignment is accepted.
  std::vector<std::uint8_t> bytes(1 + 16 * 4 * 16 + 1, 0xEE);
  const ImageView v{bytes.data() + 1, 16, 4, 16 * 16, PixelFormat::rgba32f, false};
  Renderer r;
  ASSERT_TRUE(r.render(s, {}, v).ok());
  float px[4];
  std::memcpy(px, bytes.data() + 1 + 16 * (2 * 16 + 3), sizeof px);
  EXPECT_FLOAT_EQ(px[1], 0.5f);
  EXPECT_EQ(bytes.front(), 0xEE);
  EXPECT_EQ(bytes.back(), 0xEE);

  // Depth at an odd address too, and a quad over the left half only, so that the resolve writes
  // both drawn blocks and untouched (clear) ones into the unaligned views (found by fuzz_render:
  // the SIMD resolve stored floats through misaligned pointers).
  Scene half = test::camera_scene();
  test::add_quad(half, -30, -9, 0, 9, -5, Color3(0.25f, 0.5f, 1.0f));
  std::vector<std::uint8_t> depth_bytes(1 + 16 * 4 * 4 + 1, 0xEE);
  const DepthView d{reinterpret_cast<float*>(depth_bytes.data() + 1), 16, 4, 16 * 4, false};
  for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
    RenderOptions o;
    o.path = path;
    ASSERT_TRUE(r.render(half, o, v, &d).ok());
    float z_left, z_right;
    std::memcpy(&z_left, depth_bytes.data() + 1 + 4 * (2 * 16 + 1), 4);
    std::memcpy(&z_right, depth_bytes.data() + 1 + 4 * (2 * 16 + 14), 4);
    EXPECT_LT(z_left, 1.0f);
    EXPECT_EQ(z_right, 1.0f);
    EXPECT_EQ(depth_bytes.front(), 0xEE);
    EXPECT_EQ(depth_bytes.back(), 0xEE);
    EXPECT_EQ(bytes.back(), 0xEE);
  }
}

}  // namespace
}  // namespace facet
