// Orthographic cameras (camera.hpp: Projection), a file's camera chosen by index or name
// (ModelOptions::camera) and the six up axes framing takes (UpAxis).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <tuple>

#include "facet/facet.hpp"
#include "render_support.hpp"

namespace facet {
namespace {

using test::add_quad;
using test::Canvas;

Camera ortho_camera(float half_height, float near, float far) {
  Camera c;
  c.projection = Projection::orthographic;
  c.eye = Vec3(0, 0, 0);
  c.target = Vec3(0, 0, -1);
  c.half_height = half_height;
  c.near = near;
  c.far = far;
  return c;
}

Status draw_camera_scene(const Scene& s, const ImageView& view, FrameStats* stats = nullptr, RenderOptions options = {},
                         const DepthView* depth = nullptr) {
  Renderer r;
  return r.render(s, options, view, depth, stats);
}

// Filled pixels (any non-zero colour byte) of an 8-bit image.
int filled_pixels(Canvas& c, int w, int h) {
  int n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) n += (c.byte(x, y, 0) | c.byte(x, y, 1) | c.byte(x, y, 2)) != 0;
  return n;
}

TEST(Orthographic, MatrixIsGlOrtho) {
  const Camera c = ortho_camera(2.5f, 0.5f, 40.0f);
  const float aspect = 1.6f;
  const Mat4 m = projection_matrix(c, aspect);
  // glOrtho(l, r, b, t, n, f) with r = -l = 2.5 * 1.6, t = -b = 2.5 (the OpenGL 2.1 specification, §2.11.2).
  const double r = 2.5 * 1.6, t = 2.5, n = 0.5, f = 40.0;
  Eigen::Matrix4d gl = Eigen::Matrix4d::Zero();
  gl(0, 0) = 1.0 / r, gl(1, 1) = 1.0 / t, gl(2, 2) = -2.0 / (f - n), gl(2, 3) = -(f + n) / (f - n), gl(3, 3) = 1.0;
  EXPECT_LE((m.cast<double>() - gl).cwiseAbs().maxCoeff(), 1e-7);
}

// Parallel rays: a quad covers the same pixels at every depth (a perspective camera shrinks it).
TEST(Orthographic, SizeDoesNotChangeWithDepth) {
  const int w = 48, h = 32;
  int near_pixels = 0, far_pixels = 0;
  for (const float z : {-3.0f, -30.0f}) {
    Scene s = test::camera_scene();
    s.camera = ortho_camera(2.0f, 0.0f, 50.0f);
    add_quad(s, -1, -1, 1, 1, z, Color3(1, 0, 0));
    Canvas canvas(w, h);
    ASSERT_TRUE(draw_camera_scene(s, canvas.view()).ok());
    (z == -3.0f ? near_pixels : far_pixels) = filled_pixels(canvas, w, h);
  }
  EXPECT_EQ(near_pixels, far_pixels);
  EXPECT_EQ(near_pixels, 16 * 16) << "a 2 x 2 quad in a box 4 units high, 32 pixels high: 16 x 16 pixels";
}

// Depth is linear in eye depth (glOrtho), stored as GL stores it, whatever the far / near ratio.
TEST(Orthographic, DepthIsLinearAndNeverReversed) {
  Scene s = test::camera_scene();
  s.camera = ortho_camera(2.0f, 0.0f, 1e7f);  // a far / near ratio that makes a perspective camera reversed
  add_quad(s, -1, -1, 1, 1, -250.0f, Color3(0, 1, 0));
  EXPECT_EQ(depth_mode_for(s.camera, DepthMode::automatic), DepthMode::gl);
  Canvas c(8, 8);
  std::vector<float> depth(64, -1.0f);
  const DepthView d{depth.data(), 8, 8, 8 * sizeof(float), false};
  ASSERT_TRUE(draw_camera_scene(s, c.view(), nullptr, {}, &d).ok());
  // Window depth 0.5 z_ndc + 0.5 in float: z_ndc = -1 + 5e-5 carries float's spacing near 1 (6e-8).
  EXPECT_NEAR(depth[4 * 8 + 4], 250.0 / 1e7, 1e-7);
  EXPECT_EQ(depth[0], 1.0f);
}

TEST(Orthographic, WhatAnOrthographicCameraCannotDoIsRefusedByName) {
  Scene s = test::camera_scene();
  add_quad(s, -1, -1, 1, 1, -3.0f, Color3(0, 1, 0));
  struct Case {
    Camera camera;
    const char* field;
  };
  Camera infinite = ortho_camera(1, 0, 10), flat = ortho_camera(0, 0, 10), behind = ortho_camera(1, -1, 10),
         nan_height = ortho_camera(std::nanf(""), 0, 10), inverted = ortho_camera(1, 5, 5);
  infinite.far = std::numeric_limits<float>::infinity();
  for (const Case& k : {Case{infinite, "camera.far"}, Case{flat, "camera.half_height"}, Case{behind, "camera.near"},
                        Case{nan_height, "camera.half_height"}, Case{inverted, "camera.far"}}) {
    const Status st = validate_camera(k.camera);
    EXPECT_FALSE(st.ok());
    EXPECT_EQ(st.field(), k.field) << st.message();
  }
  s.camera = ortho_camera(2, 0, 10);
  RenderOptions reversed;
  reversed.depth = DepthMode::reversed;
  Canvas c(8, 8);
  Status st = draw_camera_scene(s, c.view(), nullptr, reversed);
  EXPECT_EQ(st.code(), ErrorCode::unsupported);
  EXPECT_EQ(st.field(), "options.depth");
  s.fog.mode = FogMode::linear;
  st = draw_camera_scene(s, c.view());
  EXPECT_EQ(st.code(), ErrorCode::unsupported);
  EXPECT_EQ(st.field(), "fog.mode");
}

TEST(Orthographic, SameBytesForEveryThreadCountAndShading) {
  Result<Scene> loaded = load_scene_file(test::data_dir() + "/scenes/orthographic.json", test::scene_options());
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  for (const ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    std::vector<std::uint8_t> first;
    for (const int threads : {1, 2, 5}) {
      RenderOptions o;
      o.shading = shading;
      o.threads = threads;
      Canvas c(96, 54);
      ASSERT_TRUE(draw_camera_scene(*loaded, c.view(), nullptr, o).ok());
      if (first.empty()) {
        first = c.pixels();
        EXPECT_GT(filled_pixels(c, 96, 54), 96 * 54 / 4) << "the scene fills the box";
      } else {
        EXPECT_EQ(c.pixels(), first) << to_string(shading) << ", " << threads << " threads";
      }
    }
  }
}

TEST(Orthographic, SceneFileNamesTheFieldThatBelongsToTheOtherProjection) {
  test::TempDir dir;
  const auto load_camera = [&](const std::string& camera) {
    const std::string path = dir / "c.json";
    std::ofstream(path) << R"({"camera": )" << camera << R"(, "meshes": [{"name": "b", "shape": "cube"}], "objects": [{"mesh": "b"}]})";
    return load_scene_file(path);
  };
  Result<Scene> ok = load_camera(R"({"projection": "orthographic", "half_height": 3, "near": 0, "far": 9})");
  ASSERT_TRUE(ok.ok()) << ok.status().message();
  EXPECT_EQ(ok->camera.projection, Projection::orthographic);
  EXPECT_EQ(ok->camera.half_height, 3.0f);
  EXPECT_EQ(ok->camera.near, 0.0f);
  Result<Scene> fov = load_camera(R"({"projection": "orthographic", "fov_deg": 30})");
  ASSERT_FALSE(fov.ok());
  EXPECT_NE(fov.status().message().find("camera.fov_deg"), std::string::npos) << fov.status().message();
  Result<Scene> half = load_camera(R"({"half_height": 3})");
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("camera.half_height"), std::string::npos) << half.status().message();
  Result<Scene> unknown = load_camera(R"({"projection": "fisheye"})");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.status().message().find("camera.projection"), std::string::npos) << unknown.status().message();
}

// --- glTF cameras.

ModelOptions camera_options(const std::string& camera) {
  ModelOptions o;
  o.camera = camera;
  return o;
}

TEST(GltfCameras, FirstCameraByDefaultAndEveryCameraListed) {
  Result<Model> m = load_model(test::data_dir() + "/gltf/two_cameras.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(m->has_camera);
  EXPECT_EQ(m->scene.camera.projection, Projection::perspective);
  ASSERT_EQ(m->cameras.size(), 2u);
  EXPECT_EQ(m->cameras[0], "0 'Front' (node 'FrontCam'), perspective");
  EXPECT_EQ(m->cameras[1], "1 'Top' (node 'TopCam'), orthographic");
  EXPECT_TRUE(std::any_of(m->warnings.begin(), m->warnings.end(), [](const std::string& w) { return w.find("--camera") != std::string::npos; }));
}

TEST(GltfCameras, OrthographicCameraByIndexCameraNameOrNodeName) {
  for (const char* pick : {"1", "Top", "TopCam"}) {
    Result<Model> m = load_model(test::data_dir() + "/gltf/two_cameras.gltf", camera_options(pick));
    ASSERT_TRUE(m.ok()) << pick << ": " << m.status().message();
    const Camera& c = m->scene.camera;
    EXPECT_EQ(c.projection, Projection::orthographic) << pick;
    EXPECT_EQ(c.half_height, 1.5f) << "ymag";
    EXPECT_EQ(c.near, 0.0f);
    EXPECT_EQ(c.far, 20.0f);
    EXPECT_LE((c.eye - Vec3(3, 6, -2)).norm(), 1e-5f);
    EXPECT_LE((c.target - c.eye - Vec3(0, -1, 0)).norm(), 1e-5f) << "the node turned -90 degrees about x looks down";
    EXPECT_EQ(m->scene.viewer, ViewerMode::infinite) << "a parallel projection's viewer is at infinity (three.js)";
    EXPECT_TRUE(std::none_of(m->warnings.begin(), m->warnings.end(), [](const std::string& w) { return w.find("--camera") != std::string::npos; }));
  }
  Result<Model> front = load_model(test::data_dir() + "/gltf/two_cameras.gltf", camera_options("FrontCam"));
  ASSERT_TRUE(front.ok());
  EXPECT_EQ(front->scene.camera.projection, Projection::perspective);
}

TEST(GltfCameras, AnUnknownCameraIsAnErrorListingTheFilesCameras) {
  Result<Model> m = load_model(test::data_dir() + "/gltf/two_cameras.gltf", camera_options("Side\x1b[2J"));
  ASSERT_FALSE(m.ok());
  const std::string& msg = m.status().message();
  EXPECT_NE(msg.find("0 'Front' (node 'FrontCam'), perspective; 1 'Top'"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\x1b'), std::string::npos) << "no control character reaches a message";
  Result<Model> none = load_model(test::data_dir() + "/gltf/relief_cube.gltf", camera_options("0"));
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.status().message().find("it has none"), std::string::npos) << none.status().message();
}

TEST(GltfCameras, AMalformedOrthographicCameraNamesItsField) {
  test::TempDir dir;
  std::ifstream in(test::data_dir() + "/gltf/two_cameras.gltf");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [from, to, field] : {std::tuple{"\"ymag\": 1.5", "\"ymag\": 0", "cameras[1].orthographic.ymag"},
                                        std::tuple{"\"zfar\": 20", "\"zfar\": 0", "cameras[1].orthographic.zfar"},
                                        std::tuple{"\"znear\": 0,", "\"znear\": -1,", "cameras[1].orthographic.znear"},
                                        std::tuple{"\"xmag\": 2.4,", "", "cameras[1].orthographic.xmag"}}) {
    std::string bad = text;
    const std::size_t at = bad.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    bad.replace(at, std::strlen(from), to);
    const std::string path = dir / "bad.gltf";
    std::ofstream(path) << bad;
    Result<Model> m = load_model(path, camera_options("1"));
    ASSERT_FALSE(m.ok()) << field;
    EXPECT_NE(m.status().message().find(field), std::string::npos) << m.status().message();
  }
}

// --- Framing with an orthographic camera and any up axis.

TEST(OrthographicFraming, TheModelSpansTheAskedPartCentred) {
  Scene s;
  s.meshes.push_back({"t", make_torus(1.0f, 0.3f, 24, 12)});
  s.materials.push_back(Material{});
  Instance inst;
  inst.model = (Eigen::Translation3f(5, -2, 30) * Eigen::AngleAxisf(0.7f, Vec3(1, 2, 3).normalized())).matrix();
  s.objects.push_back(inst);
  for (const float aspect : {0.5f, 16.0f / 9.0f}) {
    ViewOptions view;
    view.projection = Projection::orthographic;
    view.azimuth_deg = 30, view.elevation_deg = 20;
    Result<Camera> c = frame_scene(s, aspect, view);
    ASSERT_TRUE(c.ok()) << c.status().message();
    ASSERT_EQ(c->projection, Projection::orthographic);
    const Eigen::Matrix4d vp = (projection_matrix(*c, aspect) * view_matrix(*c)).cast<double>();
    double x0 = 9, x1 = -9, y0 = 9, y1 = -9;
    for (const Vec3& p : s.meshes[0].mesh.positions) {
      const Eigen::Vector4d q = vp * inst.model.cast<double>() * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
      EXPECT_DOUBLE_EQ(q.w(), 1.0);
      EXPECT_LE(std::abs(q.z()), 1.0) << "inside the near and far planes";
      x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
    }
    EXPECT_NEAR(std::max(x1 - x0, y1 - y0), 2.0 * 0.85, 1e-4) << "the wider extent spans fill of the image";
    EXPECT_NEAR(x0 + x1, 0.0, 1e-4);
    EXPECT_NEAR(y0 + y1, 0.0, 1e-4);
  }
}

TEST(UpAxes, EachAxisLooksAtItsFrontWithItsUpUpAndNamesRoundTrip) {
  for (const UpAxis up : {UpAxis::y, UpAxis::z, UpAxis::x, UpAxis::neg_x, UpAxis::neg_y, UpAxis::neg_z}) {
    UpAxis parsed = UpAxis::y;
    ASSERT_TRUE(parse_up_axis(to_string(up), parsed)) << to_string(up);
    EXPECT_EQ(parsed, up);
    Scene s;
    s.meshes.push_back({"b", make_cube(1.0f, 1)});
    s.materials.push_back(Material{});
    s.objects.push_back(Instance{});
    ViewOptions view;
    view.up = up;
    Result<Camera> c = frame_scene(s, 1.0f, view);
    ASSERT_TRUE(c.ok()) << c.status().message();
    EXPECT_LE((c->up - up_vector(up)).norm(), 1e-6f) << to_string(up);
    const Vec3 from = (c->eye - c->target).normalized();
    EXPECT_LE((from - front_vector(up)).norm(), 1e-5f) << to_string(up) << ": azimuth 0 looks from the front";
    EXPECT_NEAR(front_vector(up).dot(up_vector(up)), 0.0f, 0.0f);
  }
  UpAxis out = UpAxis::y;
  EXPECT_TRUE(parse_up_axis("+z", out));
  EXPECT_EQ(out, UpAxis::z);
  EXPECT_FALSE(parse_up_axis("w", out));
  EXPECT_FALSE(parse_up_axis("--z", out));
}

}  // namespace
}  // namespace facet
