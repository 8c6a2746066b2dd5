// Framing and turntables (model.hpp): a framed model spans the asked part of the image, centred,
// from the view asked; a turntable's every frame draws the model, whether the camera is facet's
// framing or the file's own.
#include <algorithm>
#include <cmath>

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
