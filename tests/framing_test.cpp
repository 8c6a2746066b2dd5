// Framing and turntables (model.hpp): a framed model spans the asked part of the image, centred,
// from the view asked; a turntable's every frame draws the model, whether the camera is facet's
// framing or the file's own.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "facet/facet.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

// A scene of one object: `mesh` placed by `model`.
Scene one_object(Mesh mesh, const Mat4& model = Mat4::Identity()) {
  Scene s;
  s.meshes.push_back({"m", std::move(mesh)});
  s.materials.push_back(Material{});
  Instance inst;
  inst.model = model;
  s.objects.push_back(inst);
  return s;
}

// The box of the scene's vertices in normalized device coordinates (x, y) under `camera`.
struct NdcBox {
  float x0 = 1e9f, x1 = -1e9f, y0 = 1e9f, y1 = -1e9f;
};
NdcBox project(const Scene& s, const Camera& camera, float aspect) {
  const Eigen::Matrix4d vp = (projection_matrix(camera, aspect) * view_matrix(camera)).cast<double>();
  NdcBox b;
  for (const Instance& inst : s.objects) {
    for (const Vec3& p : s.meshes[inst.mesh].mesh.positions) {
      const Eigen::Vector4d w = inst.model.cast<double>() * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
      const Eigen::Vector4d c = vp * w;
      EXPECT_GT(c.w(), 0.0);
      EXPECT_LE(std::abs(c.z()), c.w()) << "a vertex outside the near or far plane";
      b.x0 = std::min(b.x0, float(c.x() / c.w())), b.x1 = std::max(b.x1, float(c.x() / c.w()));
      b.y0 = std::min(b.y0, float(c.y() / c.w())), b.y1 = std::max(b.y1, float(c.y() / c.w()));
    }
  }
  return b;
}

Mat4 placed(const Vec3& t, const Vec3& scale, float angle_deg = 0.0f) {
  Eigen::Affine3f a = Eigen::Translation3f(t) * Eigen::AngleAxisf(angle_deg * 3.14159265f / 180.0f, Vec3(1, 2, 3).normalized()) *
                      Eigen::Scaling(scale);
  return a.matrix();
}

TEST(Framing, TheModelSpansTheAskedPartOfTheImageCentred) {
  const Scene models[] = {one_object(make_torus(1.0f, 0.3f, 24, 12), placed(Vec3(5, -2, 30), Vec3(1, 1, 1), 40)),
                          one_object(make_cube(1.0f, 1), placed(Vec3(0, 0, 0), Vec3(8, 0.5f, 0.5f))),  // a long rod
                          one_object(make_uv_sphere(1.0f, 16, 8), placed(Vec3(-100, 7, 3), Vec3(0.01f, 0.01f, 0.01f)))};
  for (const Scene& s : models) {
    for (const float aspect : {0.5f, 1.0f, 16.0f / 9.0f, 3.0f}) {
      for (const auto& [az, el] : {std::pair{0.0f, 0.0f}, {90.0f, 0.0f}, {30.0f, 20.0f}, {-120.0f, -45.0f}, {0.0f, 80.0f}}) {
        for (const float fill : {0.85f, 0.5f}) {
          ViewOptions view;
          view.azimuth_deg = az, view.elevation_deg = el, view.fill = fill;
          Result<Camera> c = frame_scene(s, aspect, view);
          ASSERT_TRUE(c.ok()) << c.status().message();
          const NdcBox b = project(s, *c, aspect);
          const std::string at = "aspect " + std::to_string(aspect) + " view " + std::to_string(az) + "," + std::to_string(el);
          // The wider side spans `fill` of the image (up to the centring's last small step), the
          // other no more, and the model sits in the middle.
          const float span = std::max(b.x1 - b.x0, b.y1 - b.y0) / 2.0f;
          EXPECT_NEAR(span, fill, 0.01f * fill) << at;
          EXPECT_LE(std::max({-b.x0, b.x1, -b.y0, b.y1}), fill * 1.001f) << at;  // the camera is rounded to float
          EXPECT_NEAR(b.x0 + b.x1, 0.0f, 0.01f) << at;
          EXPECT_NEAR(b.y0 + b.y1, 0.0f, 0.01f) << at;
        }
      }
    }
  }
}

TEST(Framing, ViewsFollowGltfsConventionOrTheZUpOne) {
  const Scene s = one_object(make_cube(1.0f, 1));
  auto eye_direction = [&](float az, float el, UpAxis up) {
    ViewOptions v;
    v.azimuth_deg = az, v.elevation_deg = el, v.up = up;
    const Camera c = *frame_scene(s, 1.0f, v);
    EXPECT_EQ(c.up, up_vector(up));
    return Vec3((c.eye - c.target).normalized());
  };
  EXPECT_TRUE(eye_direction(0, 0, UpAxis::y).isApprox(Vec3(0, 0, 1), 1e-5f));   // the front: +Z faces the viewer
  EXPECT_TRUE(eye_direction(90, 0, UpAxis::y).isApprox(Vec3(1, 0, 0), 1e-5f));  // from +X
  EXPECT_TRUE(eye_direction(180, 0, UpAxis::y).isApprox(Vec3(0, 0, -1), 1e-5f));
  EXPECT_TRUE(eye_direction(0, 30, UpAxis::y).isApprox(Vec3(0, 0.5f, std::sqrt(3.0f) / 2), 1e-5f));  // from above
  EXPECT_TRUE(eye_direction(0, 0, UpAxis::z).isApprox(Vec3(0, -1, 0), 1e-5f));   // Z up: the front faces -Y
  EXPECT_TRUE(eye_direction(90, 0, UpAxis::z).isApprox(Vec3(1, 0, 0), 1e-5f));
  EXPECT_TRUE(eye_direction(0, -30, UpAxis::z).isApprox(Vec3(0, -std::sqrt(3.0f) / 2, -0.5f), 1e-5f));
  // Out of range: named.
  for (const auto& [field, v] : {std::pair{"elevation_deg", ViewOptions{0, 90}}, {"vertical_fov_deg", ViewOptions{0, 0, UpAxis::y, 180}},
                                 {"fill", ViewOptions{0, 0, UpAxis::y, 45, 0}}, {"fill", ViewOptions{0, 0, UpAxis::y, 45, 1.5f}}}) {
    Result<Camera> c = frame_scene(s, 1.0f, v);
    ASSERT_FALSE(c.ok()) << field;
    EXPECT_EQ(c.status().field(), field);
  }
  EXPECT_FALSE(frame_scene(Scene{}, 1.0f).ok());  // nothing to frame
  EXPECT_FALSE(frame_scene(s, 0.0f).ok());
}

TEST(Framing, HugeCoordinatesAreFramedAndDrawn) {
  // 1e30 is far inside a float's range; the camera's validation once squared it and refused.
  for (const float at : {1e30f, -3e35f}) {
    Scene s = one_object(make_uv_sphere(1.0f, 12, 6), placed(Vec3(at, at, 0), Vec3(at / 1e3f, at / 1e3f, at / 1e3f)));
    Result<Camera> c = frame_scene(s, 1.0f);
    ASSERT_TRUE(c.ok()) << c.status().message();
    s.camera = *c;
    add_default_lights(s);
    std::vector<std::uint8_t> px(48 * 48 * 4);
    FrameStats stats;
    ASSERT_TRUE(Renderer().render(s, {px.data(), 48, 48, 48 * 4, PixelFormat::rgba8, false}, nullptr, &stats).ok());
    EXPECT_GT(stats.pixels_filled, 48u * 48u / 4) << at << ": " << explain_empty_frame(stats);
  }
}

// An infinite projection (Camera::far = +infinity; glTF's camera without zfar) stores reversed
// depth (DepthMode::automatic): nothing is cut by a far plane, and a ball 3.3e6 units away, behind
// one 1e5 away, is drawn and lit around it. GL's depth rounds it to the far value (1.0) and
// draws it only in part; a directional shadow map still fits its casters (the frustum's far
// corners lie at infinity); the depth image holds near / w.
TEST(InfiniteProjection, ReversedDepthDrawsEverythingInDepthOrder) {
  Scene s;
  s.meshes.push_back({"sphere", make_uv_sphere(1.0f, 24, 12)});
  s.materials.push_back(Material{});
  Material red;
  red.diffuse = Color3(1, 0, 0);
  s.materials.push_back(red);
  auto at = [](const Vec3& t, float scale) {
    return Mat4(Eigen::Affine3f(Eigen::Translation3f(t) * Eigen::Scaling(scale)).matrix());
  };
  Instance near_ball;  // in front of the far one, both on the axis of view
  near_ball.model = at(Vec3(0, 0, -1e5f), 1e4f);
  near_ball.material = 1;
  Instance far_ball;  // a scale of 1e6: its normals were once too short to light (lighting/setup.cpp)
  far_ball.model = at(Vec3(0, 0, -3.3e6f), 1e6f);
  s.objects = {far_ball, near_ball};
  s.camera.eye = Vec3(0, 0, 0), s.camera.target = Vec3(0, 0, -1);
  s.camera.near = 0.05f;
  s.camera.far = std::numeric_limits<float>::infinity();
  ASSERT_TRUE(validate_camera(s.camera).ok());
  EXPECT_TRUE(projection_matrix(s.camera, 1.0f).allFinite());
  Light sun;
  sun.direction = Vec3(0.3f, -1.0f, -0.2f).normalized();
  sun.shadow.method = ShadowMethod::map;
  sun.shadow.resolution = 256;
  s.lights.push_back(sun);
  auto draw = [&](DepthMode mode, std::vector<std::uint8_t>& px, std::vector<float>& depth) {
    RenderOptions o;
    o.depth = mode;
    px.assign(64 * 64 * 4, 0);
    depth.assign(64 * 64, -1.0f);
    DepthView dv{depth.data(), 64, 64, 64 * sizeof(float), false};
    FrameStats stats;
    EXPECT_TRUE(Renderer().render(s, o, {px.data(), 64, 64, 64 * 4, PixelFormat::rgba8, false}, &dv, &stats).ok());
    EXPECT_EQ(stats.triangles_outside, 0u);  // nothing beyond a far plane
    return stats.pixels_filled;
  };
  std::vector<std::uint8_t> px, gl_px;
  std::vector<float> depth, gl_depth;
  const std::uint64_t filled = draw(DepthMode::automatic, px, depth);
  const std::uint64_t gl_filled = draw(DepthMode::gl, gl_px, gl_depth);
  EXPECT_GT(filled, gl_filled + 64);
  // The centre is the near, red ball's; around it the far ball, lit (white, above ambient).
  const std::uint8_t* c = &px[(32 * 64 + 32) * 4];
  EXPECT_GT(c[0], c[1] + 20);
  int grey = 0;
  for (std::size_t i = 0; i < px.size(); i += 4) grey += px[i] > 40 && px[i] == px[i + 1] && px[i + 1] == px[i + 2];
  EXPECT_GT(grey, 200);
  // Depth: near / w; the red ball's nearest point is 9e4 away, the far ball's 2.3e6 (its centre 3.3e6).
  EXPECT_NEAR(depth[32 * 64 + 32], 0.05f / 9e4f, 0.02f * 0.05f / 9e4f);
  EXPECT_GT(depth[10 * 64 + 32], 0.05f / 3.3e6f);
  EXPECT_LT(depth[10 * 64 + 32], 0.05f / 2.3e6f);
  EXPECT_EQ(depth[0], 0.0f);  // nothing drawn: infinitely far
  EXPECT_EQ(gl_depth[0], 1.0f);
}

// Near 0.05 and far 1e6 (a ratio of 2e7): two quads 1 unit apart, 1e4 units away. GL's float
// depth cannot tell them apart (the depths differ by about 5e-10, a float near 1 steps by 6e-8):
// the front one, drawn second, fails the LESS test where the back one is; reversed depth draws
// the front one everywhere.
TEST(InfiniteProjection, ReversedDepthDoesNotZFight) {
  Scene s;
  s.meshes.push_back({"quad", make_plane(1.0f, 1.0f, 8)});
  Material front, back;
  front.diffuse = Color3(1, 0, 0), back.diffuse = Color3(0, 1, 0);
  s.materials = {front, back};
  auto quad = [](float z, std::uint32_t material) {
    Instance i;
    i.model = Mat4(Eigen::Affine3f(Eigen::Translation3f(Vec3(0, 0, z)) * Eigen::AngleAxisf(1.5707963f, Vec3(1, 0, 0)) *
                                   Eigen::Scaling(3e4f))
                       .matrix());
    i.material = material;
    i.double_sided = true;
    return i;
  };
  s.objects = {quad(-1e4f - 1.0f, 1), quad(-1e4f, 0)};  // the back one first: an equal depth keeps it
  s.camera.eye = Vec3(0, 0, 0), s.camera.target = Vec3(0, 0, -1);
  s.camera.near = 0.05f, s.camera.far = 1e6f;
  Light l;
  l.direction = Vec3(0, 0, -1);
  s.lights = {l};
  auto greens = [&](DepthMode mode) {
    RenderOptions o;
    o.depth = mode;
    std::vector<std::uint8_t> px(64 * 64 * 4);
    EXPECT_TRUE(Renderer().render(s, o, {px.data(), 64, 64, 64 * 4, PixelFormat::rgba8, false}).ok());
    int n = 0, red = 0;
    for (std::size_t i = 0; i < px.size(); i += 4) n += px[i + 1] > px[i], red += px[i] > px[i + 1];
    EXPECT_GT(n + red, 64 * 64 / 2);  // the quads fill the view
    return n;
  };
  EXPECT_GT(greens(DepthMode::gl), 64);      // z-fighting: the back quad shows through
  EXPECT_EQ(greens(DepthMode::reversed), 0);
  EXPECT_EQ(greens(DepthMode::automatic), 0);  // far / near > 1e5: reversed
}

// Reversed depth is the same bytes on every ISA and for any thread count (depth images bit for
// bit; colour images across threads); the scalar rasterizer interpolates depth from barycentric
// weights, the SIMD one from a plane (as in GL mode), so the two agree to a float rounding.
TEST(InfiniteProjection, ReversedDepthIsTheSameOnEveryIsaAndThreadCount) {
  Scene s = make_default_scene();
  s.camera.near = 0.01f;
  s.camera.far = std::numeric_limits<float>::infinity();
  auto draw = [&](LightingPath path, Isa isa, int threads, std::vector<std::uint8_t>& px, std::vector<float>& depth) {
    RenderOptions o;
    o.depth = DepthMode::reversed;
    o.path = path, o.isa = isa, o.threads = threads, o.shading = ShadingMode::phong;
    px.assign(96 * 64 * 4, 0);
    depth.assign(96 * 64, -1.0f);
    DepthView dv{depth.data(), 96, 64, 96 * sizeof(float), false};
    ASSERT_TRUE(Renderer().render(s, o, {px.data(), 96, 64, 96 * 4, PixelFormat::rgba8, false}, &dv).ok());
  };
  auto same_bits = [](const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
  };
  std::vector<std::uint8_t> scalar_px, px1, px;
  std::vector<float> scalar_depth, depth1, depth;
  draw(LightingPath::scalar, Isa::best, 1, scalar_px, scalar_depth);
  int drawn = 0;
  for (const float d : scalar_depth) {
    drawn += d > 0.0f;
    EXPECT_GE(d, 0.0f);
    EXPECT_LE(d, 1.0f);
  }
  EXPECT_GT(drawn, 96 * 64 / 4);
  draw(LightingPath::scalar, Isa::best, 3, px, depth);
  EXPECT_EQ(px, scalar_px);
  EXPECT_TRUE(same_bits(depth, scalar_depth));
  bool first = true;
  for (const Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (!isa_supported(isa)) continue;
    for (const int threads : {1, 3}) {
      draw(LightingPath::simd, isa, threads, px, depth);
      if (first) {
        px1 = px, depth1 = depth, first = false;
        for (std::size_t i = 0; i < depth.size(); ++i) EXPECT_NEAR(depth[i], scalar_depth[i], 1e-6f * scalar_depth[i]) << i;
        continue;
      }
      EXPECT_TRUE(same_bits(depth, depth1)) << to_string(isa) << " threads " << threads;
      if (threads != 1) {
        EXPECT_EQ(px, px1) << to_string(isa);
      }
    }
  }
}

// A turntable: frames of the camera orbiting the box's centre, the rig turning with it.
std::vector<std::uint64_t> turntable(Scene s, int frames, std::size_t rig_first) {
  const Bounds b = scene_bounds(s);
  const Vec3 centre = 0.5f * (b.min + b.max);
  const Camera start = s.camera;
  const std::vector<Light> lights = s.lights;
  std::vector<std::uint64_t> filled;
  std::vector<std::uint8_t> px(64 * 48 * 4);
  for (int k = 0; k < frames; ++k) {
    const float angle = 360.0f * float(k) / float(frames);
    s.camera = orbit_camera(start, centre, UpAxis::y, angle);
    EXPECT_NEAR((s.camera.eye - centre).norm(), (start.eye - centre).norm(), 1e-4f * (start.eye - centre).norm());
    EXPECT_EQ(s.camera.target, centre);
    for (std::size_t i = rig_first; i < lights.size(); ++i) s.lights[i] = orbit_light(lights[i], centre, UpAxis::y, angle);
    FrameStats stats;
    EXPECT_TRUE(Renderer().render(s, {px.data(), 64, 48, 64 * 4, PixelFormat::rgba8, false}, nullptr, &stats).ok());
    filled.push_back(stats.pixels_filled);
  }
  return filled;
}

TEST(Turntable, EveryFrameDrawsTheModel) {
  // A model whose file camera looks at it from 6 units away, off the origin: the orbit is about
  // the model's centre at that distance (it once was about a point one unit in front of the eye).
  Result<Model> m = load_model(test::data_dir() + "/gltf/tetrahedron_camera.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(m->has_camera);
  Scene s = m->scene;
  add_default_lights(s);
  for (const std::uint64_t f : turntable(s, 24, 0)) EXPECT_GT(f, 64u * 48u / 20);
  // The same with facet's framing of a long rod, seen end-on at first: every frame holds it.
  Scene rod = one_object(make_cube(1.0f, 1), placed(Vec3(1, 2, 3), Vec3(0.3f, 0.3f, 6.0f)));
  rod.camera = *frame_scene(rod, 64.0f / 48.0f);
  add_default_lights(rod);
  for (const std::uint64_t f : turntable(rod, 24, 0)) EXPECT_GT(f, 64u * 48u / 50);
}

TEST(Turntable, ALightThatTurnsWithTheCameraKeepsThePictureOfASphere) {
  // A sphere turned under a rig that turns with the camera looks the same in every frame; with the
  // rig fixed in the world, the lit side moves.
  Scene s = one_object(make_uv_sphere(1.0f, 48, 24));
  s.camera = *frame_scene(s, 64.0f / 48.0f);
  add_default_lights(s);
  const std::vector<std::uint64_t> turning = turntable(s, 4, 0);
  for (const std::uint64_t f : turning) EXPECT_EQ(f, turning[0]);
  std::vector<std::uint8_t> a(64 * 48 * 4), b(64 * 48 * 4);
  const Bounds bounds = scene_bounds(s);
  const Vec3 centre = 0.5f * (bounds.min + bounds.max);
  Scene turned = s, fixed = s;
  turned.camera = fixed.camera = orbit_camera(s.camera, centre, UpAxis::y, 90.0f);
  for (Light& l : turned.lights) l = orbit_light(l, centre, UpAxis::y, 90.0f);
  Scene first = s;
  std::vector<std::uint8_t> c(64 * 48 * 4);
  ASSERT_TRUE(Renderer().render(first, {c.data(), 64, 48, 64 * 4, PixelFormat::rgba8, false}).ok());
  ASSERT_TRUE(Renderer().render(turned, {a.data(), 64, 48, 64 * 4, PixelFormat::rgba8, false}).ok());
  ASSERT_TRUE(Renderer().render(fixed, {b.data(), 64, 48, 64 * 4, PixelFormat::rgba8, false}).ok());
  auto differ = [](const std::vector<std::uint8_t>& x, const std::vector<std::uint8_t>& y) {
    int n = 0;
    for (std::size_t i = 0; i < x.size(); ++i) n += std::abs(int(x[i]) - int(y[i])) > 2;
    return n;
  };
  EXPECT_LT(differ(c, a), 64 * 48 / 50);  // the turned rig: (almost) the same picture
  EXPECT_GT(differ(c, b), 64 * 48 / 10);  // the fixed rig: the lit side has moved
}

}  // namespace
}  // namespace facet
