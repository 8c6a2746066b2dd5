// Environment mapping (Material::environment): the stage against a double-precision twin of GL's
// texgen and cube-face rules, rendered mirrors against exact reflection rays of a true sphere,
// per vertex against per pixel, where the method breaks (the sphere map's singular direction,
// grazing angles, a zero normal, 1x1 faces), determinism across ISAs and threads, and the scene
// file's errors.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "pixel/stages.hpp"
#include "render_support.hpp"
#include "texture/sampler.hpp"

namespace facet {
namespace {

using test::Canvas;

// A size x size face from a function of the texel centre's (s, t), t from the picture's top (GL's
// face convention), top row first as make_texture takes it.
template <class Fn>
Texture face_from(int size, Fn&& colour) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size * size) * 4);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const std::array<std::uint8_t, 4> c = colour((i + 0.5) / size, (j + 0.5) / size);
      std::memcpy(&rgba[static_cast<std::size_t>(j * size + i) * 4], c.data(), 4);
    }
  TextureOptions o;
  o.filter = TextureFilter::bilinear;
  o.wrap = TextureWrap::clamp;
  Result<Texture> t = make_texture("face", size, size, rgba, o);
  EXPECT_TRUE(t.ok()) << t.status().message();
  return std::move(*t);
}

// The direction GL's table 3.21 maps to (s, t) of face f (t from the picture's top).
Eigen::Vector3d face_direction(int f, double s, double t) {
  const double sc = 2 * s - 1, tc = 2 * t - 1;
  const Eigen::Vector3d d[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc}, {sc, -1, -tc}, {sc, -tc, 1}, {-sc, -tc, -1}};
  return d[f];
}

// A smooth sky: the colour is an affine function of the unit direction, so bilinear filtering is
// nearly exact and the differences measured are those of the lookup.
std::array<std::uint8_t, 4> sky(const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = d.normalized();
  auto c = [](double v) { return static_cast<std::uint8_t>(std::lround(255.0 * (0.5 + 0.45 * v))); };
  return {c(u.x()), c(u.y()), c(u.z()), 255};
}

// The double-precision twin: GL's reflection and cube-face selection, then the reference sampler.
struct Exact {
  texture::Sampler faces[6];
  Eigen::Matrix3d to_world = Eigen::Matrix3d::Identity();
  Eigen::Vector3d colour(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
    const Eigen::Vector3d u = p.normalized(), nn = n.normalized();
    const Eigen::Vector3d r = to_world * (u - 2.0 * nn * nn.dot(u));
    const auto c = texture::sample_cube_reference(faces, r.x(), r.y(), r.z());
    return {c[0], c[1], c[2]};
  }
};

// A scene of one mirror ball (radius 1 at the origin, seen from +z) whose colour is the
// environment alone (mix at strength 1, no light), cube-mapped with `sky` faces of `size`.
Scene mirror_ball(int size, int segments, EnvironmentMode mode = EnvironmentMode::cube) {
  Scene s;
  s.camera.eye = Vec3(0, 0, 3.2f);
  s.camera.near = 0.5f;
  s.camera.far = 10.0f;
  s.global_ambient = Color3(0, 0, 0);
  for (int f = 0; f < 6; ++f) {
    s.textures.push_back(face_from(size, [f](double u, double v) { return sky(face_direction(f, u, v)); }));
  }
  Material m;
  m.ambient = m.diffuse = Color3(0, 0, 0);
  m.environment.mode = mode;
  m.environment.blend = EnvironmentBlend::mix;
  m.environment.strength = 1.0f;
  for (int f = 0; f < 6; ++f) m.environment.maps[f] = mode == EnvironmentMode::cube || f == 0 ? f : kNoTexture;
  s.materials.push_back(m);
  s.meshes.push_back({"ball", make_uv_sphere(1.0f, segments, segments / 2)});
  s.objects.push_back({});
  return s;
}

struct Errors {
  double mean = 0, largest = 0, within2 = 0;  // 8-bit steps; share of pixels within 2 steps
  int pixels = 0;
};

// Every pixel whose ray meets the true sphere well inside its silhouette, against the exact
// reflection there.
Errors against_exact(const Scene& s, ShadingMode shading, LightingPath path = LightingPath::simd, Isa isa = Isa::best) {
  const int w = 160, h = 160;
  Canvas c(w, h);
  RenderOptions o = test::gl_options();
  o.shading = shading;
  o.path = path;
  o.isa = isa;
  Renderer r;
  EXPECT_TRUE(r.render(s, o, c.view()).ok());
  Exact exact;
  for (std::size_t f = 0; f < 6; ++f) exact.faces[f] = texture::make_sampler(s.textures[f]);
  const double fov = s.camera.vertical_fov_deg * M_PI / 180.0, k = std::tan(0.5 * fov);
  const Eigen::Vector3d eye = s.camera.eye.cast<double>();
  const Eigen::Vector3d centre = s.objects[0].model.cast<double>().topRightCorner<3, 1>();
  const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
  exact.to_world = to_eye.transpose();
  Errors e;
  double sum = 0;
  int close = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d dir =
          to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * k, (1 - 2.0 * (y + 0.5) / h) * k, -1).normalized();
      // Ray eye + t dir against the unit sphere; only pixels well inside the silhouette (the
      // tessellated outline differs from the true one).
      const Eigen::Vector3d oc = eye - centre;
      const double b = oc.dot(dir), cc = oc.squaredNorm() - 1.0, disc = b * b - cc;
      if (disc < 0.15) continue;
      const double t = -b - std::sqrt(disc);
      const Eigen::Vector3d hit = eye + t * dir;  // world space; the unit sphere's normal is hit - centre
      const Eigen::Vector3d want = exact.colour(to_eye * (hit - eye), to_eye * (hit - centre));
      for (int ch = 0; ch < 3; ++ch) {
        const double d = std::abs(c.byte(x, y, ch) - 255.0 * want[ch]);
        sum += d;
        e.largest = std::max(e.largest, d);
      }
      close += std::abs(c.byte(x, y, 0) - 255.0 * want[0]) <= 2.5 && std::abs(c.byte(x, y, 1) - 255.0 * want[1]) <= 2.5 &&
               std::abs(c.byte(x, y, 2) - 255.0 * want[2]) <= 2.5;
      ++e.pixels;
    }
  }
  e.mean = e.pixels ? sum / (3.0 * e.pixels) : 0;
  e.within2 = e.pixels ? double(close) / e.pixels : 0;
  return e;
}

// The stage's float arithmetic against the double twin on random points and normals.
TEST(EnvironmentStage, CoordinatesMatchGLsRulesInDouble) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const float to_world[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double sphere_err = 0, cube_err = 0;
  int faces_disagree = 0;
  for (int i = 0; i < 20000; ++i) {
    const float p[3] = {u(rng) * 3, u(rng) * 3, -0.5f - 4 * std::abs(u(rng))}, n[3] = {u(rng), u(rng), u(rng)};
    const Eigen::Vector3d pd(p[0], p[1], p[2]), nd = Eigen::Vector3d(n[0], n[1], n[2]).normalized();
    const Eigen::Vector3d ud = pd.normalized(), r = ud - 2.0 * nd * nd.dot(ud);
    float c[3];
    pixel::environment_coords(EnvironmentMode::sphere, to_world, p, n, c);
    const double m = 2.0 * std::sqrt(r.x() * r.x() + r.y() * r.y() + (r.z() + 1) * (r.z() + 1));
    // The float error grows as 1/m toward the singular direction (r / m with r rounded): bounded
    // as error x m.
    sphere_err = std::max({sphere_err, m * std::abs(c[0] - (r.x() / m + 0.5)), m * std::abs(c[1] - (r.y() / m + 0.5))});
    pixel::environment_coords(EnvironmentMode::cube, to_world, p, n, c);
    float face, s, t;
    pixel::cube_face(c, face, s, t);
    const Eigen::Vector3d a = r.cwiseAbs();
    const int f = a.x() >= a.y() && a.x() >= a.z() ? (r.x() >= 0 ? 0 : 1) : a.y() >= a.z() ? (r.y() >= 0 ? 2 : 3) : (r.z() >= 0 ? 4 : 5);
    if (static_cast<int>(face) != f) {  // only where two axes tie to float precision
      ++faces_disagree;
      double sorted[3] = {a.x(), a.y(), a.z()};
      std::sort(sorted, sorted + 3);
      EXPECT_LT(sorted[2] - sorted[1], 1e-5 * sorted[2]);
      continue;
    }
    const Eigen::Vector3d d = face_direction(f, s, 1.0 - t).normalized();
    cube_err = std::max(cube_err, (d - r.normalized()).norm());
  }
  EXPECT_LT(sphere_err, 1e-6);
  EXPECT_LT(cube_err, 4e-6);
  EXPECT_LT(faces_disagree, 5);
}

TEST(EnvironmentStage, SingularAndDegenerateInputsGiveFiniteCoordinates) {
  const float to_world[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  float c[3];
  // r = (0, 0, -1): a normal across the view ray at the silhouette, straight ahead.
  const float ahead[3] = {0, 0, -2}, across[3] = {1, 0, 0};
  pixel::environment_coords(EnvironmentMode::sphere, to_world, ahead, across, c);
  EXPECT_EQ(c[0], 1.0f);  // the map's rim
  EXPECT_EQ(c[1], 0.5f);
  // A zero normal reflects nothing; a point at the eye looks down -z; both give finite values.
  const float zero[3] = {0, 0, 0};
  for (EnvironmentMode mode : {EnvironmentMode::sphere, EnvironmentMode::cube, EnvironmentMode::normal}) {
    pixel::environment_coords(mode, to_world, ahead, zero, c);
    for (float v : c) EXPECT_TRUE(std::isfinite(v)) << to_string(mode);
    pixel::environment_coords(mode, to_world, zero, across, c);
    for (float v : c) EXPECT_TRUE(std::isfinite(v)) << to_string(mode);
  }
  // Grazing: sphere coordinates stay in [0, 1] as the normal turns to 90 degrees from the view.
  for (int k = 0; k <= 1000; ++k) {
    const float a = 1.5707964f * static_cast<float>(k) / 1000.0f, n[3] = {std::sin(a), 0, std::cos(a)};
    pixel::environment_coords(EnvironmentMode::sphere, to_world, ahead, n, c);
    EXPECT_TRUE(c[0] >= 0.0f && c[0] <= 1.0f && c[1] >= 0.0f && c[1] <= 1.0f) << a;
  }
  // A zero reflection reads a face's centre, finitely.
  const float r0[3] = {0, 0, 0};
  float face, s, t;
  pixel::cube_face(r0, face, s, t);
  EXPECT_EQ(face, 0.0f);
  EXPECT_EQ(s, 0.5f);
  EXPECT_EQ(t, 0.5f);
}

// Per pixel (Phong) against exact reflection rays of the true sphere: the error is the
// tessellation's and the float lookup's; per vertex (Gouraud, GL's texgen) is coarser. Figures of
// the last run are in docs/environment.md.
TEST(Environment, MirrorBallAgainstExactReflections) {
  for (int segments : {96, 24}) {
    const Scene s = mirror_ball(32, segments);
    const Errors phong = against_exact(s, ShadingMode::phong);
    const Errors gouraud = against_exact(s, ShadingMode::gouraud);
    ASSERT_GT(phong.pixels, 5000);
    std::printf("mirror ball, %d segments, 32^2 faces: per pixel mean %.3f largest %.0f within 2: %.4f; "
                "per vertex mean %.3f largest %.0f within 2: %.4f\n",
                segments, phong.mean, phong.largest, phong.within2, gouraud.mean, gouraud.largest, gouraud.within2);
    EXPECT_LT(phong.mean, gouraud.mean) << segments;
    if (segments == 96) {  // fine enough that the lookup, not the tessellation, dominates
      EXPECT_LE(phong.mean, 1.0) << "largest " << phong.largest;
      EXPECT_GE(phong.within2, 0.97);
      EXPECT_LE(gouraud.mean, 1.0);
    }
  }
  // Cube maps are looked up in world space: the same room from a camera on +x, looking back, the
  // ball off the view axis (so that eye-space positions and normals differ in every component).
  Scene turned = mirror_ball(32, 96);
  turned.camera.eye = Vec3(3.2f, 0.0f, 0.0f);
  turned.objects[0].model.topRightCorner<3, 1>() = Vec3(0.0f, 0.25f, 0.3f);
  turned.camera.target = Vec3(0.0f, 0.0f, 0.0f);
  for (ShadingMode shading : {ShadingMode::phong, ShadingMode::gouraud}) {
    const Errors e = against_exact(turned, shading);
    EXPECT_LE(e.mean, 1.0) << to_string(shading);
    EXPECT_GE(e.within2, 0.97) << to_string(shading);
  }
  const Scene s = mirror_ball(32, 96);
  // The scalar path runs the same stages.
  const Errors scalar = against_exact(s, ShadingMode::phong, LightingPath::scalar);
  EXPECT_LE(scalar.mean, 1.0);
  EXPECT_GE(scalar.within2, 0.97);
}

TEST(Environment, OneTexelFacesGiveTheFaceColours) {
  Scene s = mirror_ball(1, 48);
  const Errors e = against_exact(s, ShadingMode::phong);
  EXPECT_GT(e.pixels, 1000);
  EXPECT_LE(e.mean, 1.0);
}

std::vector<std::uint8_t> picture(const Scene& s, ShadingMode shading, LightingPath path, Isa isa, int threads) {
  Canvas c(96, 96);
  RenderOptions o = test::gl_options();
  o.shading = shading;
  o.path = path;
  o.isa = isa;
  o.threads = threads;
  Renderer r;
  EXPECT_TRUE(r.render(s, o, c.view()).ok());
  std::vector<std::uint8_t> bytes(96 * 96 * 4);
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x)
      for (int ch = 0; ch < 4; ++ch) bytes[static_cast<std::size_t>((y * 96 + x) * 4 + ch)] = static_cast<std::uint8_t>(c.byte(x, y, ch));
  return bytes;
}

// The same bytes on every ISA and thread count, for each mode and shading (the ball's colour is
// the environment alone, so the lighting kernels' own ISA differences do not enter).
TEST(Environment, SameBytesOnEveryIsaAndThreadCount) {
  for (EnvironmentMode mode : {EnvironmentMode::cube, EnvironmentMode::sphere, EnvironmentMode::normal}) {
    const Scene s = mirror_ball(8, 40, mode);
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      const auto first = picture(s, shading, LightingPath::simd, Isa::sse2, 1);
      for (Isa isa : {Isa::avx2, Isa::avx512}) {
        if (!isa_supported(isa)) continue;
        EXPECT_EQ(picture(s, shading, LightingPath::simd, isa, 1), first) << to_string(mode) << " " << to_string(shading) << " " << to_string(isa);
      }
      for (int threads : {2, 3}) {
        EXPECT_EQ(picture(s, shading, LightingPath::simd, Isa::sse2, threads), first) << to_string(mode) << " " << threads;
      }
      EXPECT_EQ(picture(s, shading, LightingPath::scalar, Isa::best, 1), picture(s, shading, LightingPath::scalar, Isa::best, 3));
    }
  }
}

TEST(Environment, BlendsAsDocumented) {
  // A flat quad facing the camera, its textured colour c = the material's emission (no light),
  // a one-texel sphere map E: add c + k E, modulate c (1 - k + k E), mix c (1 - k) + k E.
  const float c = 0.4f, E = 0.8f, k = 0.5f;
  auto run = [&](EnvironmentBlend blend) {
    Scene s;
    s.global_ambient = Color3(0, 0, 0);
    const std::uint8_t texel[4] = {static_cast<std::uint8_t>(std::lround(E * 255)), 0, 0, 255};
    s.textures.push_back(*make_texture("e", 1, 1, std::span<const std::uint8_t>(texel, 4), {}));
    Material m;
    m.ambient = m.diffuse = Color3(0, 0, 0);
    m.emissive = Color3(c, c, c);
    m.environment.mode = EnvironmentMode::sphere;
    m.environment.maps[0] = 0;
    m.environment.strength = k;
    m.environment.blend = blend;
    s.materials.push_back(m);
    s.meshes.push_back({"quad", make_plane(4.0f, 4.0f, 1)});
    Instance inst;
    inst.model = Eigen::Affine3f(Eigen::AngleAxisf(float(M_PI / 2), Eigen::Vector3f::UnitX())).matrix();
    s.objects.push_back(inst);
    Canvas canvas(16, 16);
    RenderOptions o = test::gl_options();
    o.shading = ShadingMode::phong;
    Renderer r;
    EXPECT_TRUE(r.render(s, o, canvas.view()).ok());
    return std::array<int, 2>{canvas.byte(8, 8, 0), canvas.byte(8, 8, 1)};
  };
  const double e = std::lround(E * 255) / 255.0;
  const auto add = run(EnvironmentBlend::add), modulate = run(EnvironmentBlend::modulate), mix = run(EnvironmentBlend::mix);
  EXPECT_NEAR(add[0], 255 * (c + k * e), 1.0);
  EXPECT_NEAR(add[1], 255 * c, 1.0);
  EXPECT_NEAR(modulate[0], 255 * c * (1 - k + k * e), 1.0);
  EXPECT_NEAR(modulate[1], 255 * c * (1 - k), 1.0);
  EXPECT_NEAR(mix[0], 255 * (c * (1 - k) + k * e), 1.0);
  EXPECT_NEAR(mix[1], 255 * c * (1 - k), 1.0);
}

// Maps are read clamped to the edge whatever the texture's wrap mode: a 2 x 1 normal map (left
// texel black, right white) made to repeat, on a quad whose normals lean 60 degrees towards +x,
// reads s = 1/2 + sin 60 / 2 = 0.93, in the right texel's outer half: white when clamped, a third
// black when the filter wraps round to the left texel.
TEST(Environment, MapsAreClampedToTheEdge) {
  Scene s = test::camera_scene();
  test::add_quad(s, -5, -5, 5, 5, -3, Color3(0.2f, 0.2f, 0.2f));
  const float lean = std::sin(60.0f * float(M_PI) / 180.0f);
  s.meshes.back().mesh.normals.assign(4, Vec3(lean, 0.0f, 0.5f));
  const std::uint8_t texels[8] = {0, 0, 0, 255, 255, 255, 255, 255};
  TextureOptions o;
  o.filter = TextureFilter::bilinear;
  o.wrap = TextureWrap::repeat;
  Result<Texture> map = make_texture("lean", 2, 1, texels, o);
  ASSERT_TRUE(map.ok());
  s.textures.push_back(std::move(*map));
  Environment& e = s.materials.back().environment;
  e.mode = EnvironmentMode::normal;
  e.maps[0] = 0;
  e.blend = EnvironmentBlend::mix;
  e.strength = 1.0f;
  for (const ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (const LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
      SCOPED_TRACE(std::string(to_string(shading)) + " " + to_string(path));
      Canvas c(32, 32);
      RenderOptions opt = test::gl_options();
      opt.shading = shading;
      opt.path = path;
      Renderer r;
      ASSERT_TRUE(r.render(s, opt, c.view()).ok());
      EXPECT_GE(c.byte(16, 16, 0), 254);
    }
  }
}

TEST(Environment, ValidationNamesTheField) {
  Scene s = mirror_ball(4, 12);
  s.materials[0].environment.maps[3] = kNoTexture;
  Status st = validate_scene(s);
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(st.field(), "materials[0].environment.maps[3]");
  s = mirror_ball(4, 12);
  s.textures[2] = face_from(8, [](double, double) { return std::array<std::uint8_t, 4>{0, 0, 0, 255}; });
  st = validate_scene(s);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("square and the same size"), std::string::npos) << st.message();
  s = mirror_ball(4, 12);
  s.materials[0].environment.strength = 1.5f;
  EXPECT_FALSE(validate_scene(s).ok());
  s = mirror_ball(4, 12, EnvironmentMode::sphere);
  s.materials[0].environment.maps[1] = 1;  // unused by a sphere map
  EXPECT_FALSE(validate_scene(s).ok());
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// A mirror ball (radius 0.5) at the centre of a closed room (half-size 6) whose six walls glow,
// each in two halves (split along the next axis: colour f where that coordinate is positive, its
// complement where negative), seen from inside the room.
Color3 wall_colour(int f, bool positive_half) {
  const Color3 colours[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  return positive_half ? colours[f] : Color3(1, 1, 1) - colours[f];
}

Scene mirror_in_room(int resolution) {
  Scene s;
  s.camera.eye = Vec3(0.3f, 0.4f, 3.0f);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.near = 0.1f;
  s.camera.far = 50.0f;
  s.global_ambient = Color3(0, 0, 0);
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const float side = f % 2 == 0 ? 6.0f : -6.0f;
    for (int half = 0; half < 2; ++half) {
      Material m;
      m.ambient = m.diffuse = Color3(0, 0, 0);
      m.emissive = wall_colour(f, half == 0);
      s.materials.push_back(m);
      Mesh quad;
      const float b0 = half == 0 ? 0.0f : -6.0f, b1 = half == 0 ? 6.0f : 0.0f;
      for (const auto& [u, v] : {std::pair{b0, -6.0f}, std::pair{b1, -6.0f}, std::pair{b1, 6.0f}, std::pair{b0, 6.0f}}) {
        Vec3 p = Vec3::Zero();
        p[a] = side, p[b] = u, p[c] = v;
        quad.positions.push_back(p);
        Vec3 n = Vec3::Zero();
        n[a] = side > 0 ? -1.0f : 1.0f;
        quad.normals.push_back(n);
      }
      quad.triangles = {{0, 1, 2}, {0, 2, 3}};
      s.meshes.push_back({"wall", quad});
      Instance wall;
      wall.mesh = static_cast<std::uint32_t>(s.meshes.size() - 1);
      wall.material = static_cast<std::uint32_t>(s.materials.size() - 1);
      wall.double_sided = true;
      s.objects.push_back(wall);
    }
  }
  Material chrome;
  chrome.ambient = chrome.diffuse = Color3(0, 0, 0);
  chrome.environment.mode = EnvironmentMode::cube;
  chrome.environment.dynamic = true;
  chrome.environment.resolution = resolution;
  chrome.environment.blend = EnvironmentBlend::mix;
  s.materials.push_back(chrome);
  s.meshes.push_back({"ball", make_uv_sphere(0.5f, 64, 32)});
  Instance ball;
  ball.mesh = static_cast<std::uint32_t>(s.meshes.size() - 1);
  ball.material = static_cast<std::uint32_t>(s.materials.size() - 1);
  s.objects.push_back(ball);
  return s;
}

TEST(DynamicEnvironment, MirrorBallShowsTheWallItReflects) {
  const Scene s = mirror_in_room(32);
  // Without culling too: the ball's inside would then be drawn in its own faces, were it not left out.
  for (auto [shading, cull] : {std::pair{ShadingMode::phong, CullMode::back}, std::pair{ShadingMode::gouraud, CullMode::back},
                               std::pair{ShadingMode::phong, CullMode::none}}) {
    const int w = 96, h = 96;
    Canvas c(w, h);
    RenderOptions o = test::gl_options();
    o.shading = shading;
    o.cull = cull;
    Renderer r;
    ASSERT_TRUE(r.render(s, o, c.view()).ok());
    const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
    const Eigen::Vector3d eye = s.camera.eye.cast<double>();
    const double k = std::tan(0.5 * s.camera.vertical_fov_deg * M_PI / 180.0);
    int checked = 0, wrong = 0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const Eigen::Vector3d dir = (to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * k,
                                                                           (1 - 2.0 * (y + 0.5) / h) * k, -1))
                                        .normalized();
        const double b = eye.dot(dir), disc = b * b - (eye.squaredNorm() - 0.25);
        if (disc < 0.02) continue;  // off the ball or near its outline
        const Eigen::Vector3d hit = eye + (-b - std::sqrt(disc)) * dir, n = hit.normalized();
        const Eigen::Vector3d refl = dir - 2.0 * n * n.dot(dir);
        // Where the reflection from the ball's centre (a cube map's assumption) meets the walls.
        const Eigen::Vector3d a = refl.cwiseAbs();
        int axis = 0;
        a.maxCoeff(&axis);
        const Eigen::Vector3d on_wall = refl * (6.0 / a[axis]);
        const int f = 2 * axis + (refl[axis] >= 0 ? 0 : 1), split = (axis + 1) % 3, other = (axis + 2) % 3;
        // Away from the walls' edges and the halves' seam (parallax from the surface: <= 0.5).
        if (std::abs(on_wall[split]) < 1.0 || std::abs(on_wall[split]) > 5.0 || std::abs(on_wall[other]) > 5.0) continue;
        const Color3 want = wall_colour(f, on_wall[split] > 0);
        ++checked;
        bool ok = true;
        for (int ch = 0; ch < 3; ++ch) ok = ok && std::abs(c.byte(x, y, ch) - 255.0 * want[ch]) <= 2.0;
        wrong += !ok;
      }
    }
    EXPECT_GT(checked, 300) << to_string(shading);
    EXPECT_LE(wrong, checked / 50) << to_string(shading) << ": " << wrong << " of " << checked;
  }
}

// The faces are passes of the frame: the same bytes for any thread count and ISA, and the
// reflector is left out of its own faces (a ball that saw itself would show its own grey).
TEST(DynamicEnvironment, SameBytesOnEveryIsaAndThreadCount) {
  const Scene s = mirror_in_room(16);
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::phong}) {
    const auto first = picture(s, shading, LightingPath::simd, Isa::sse2, 1);
    for (Isa isa : {Isa::avx2, Isa::avx512}) {
      if (isa_supported(isa)) {
        EXPECT_EQ(picture(s, shading, LightingPath::simd, isa, 1), first) << to_string(isa);
      }
    }
    EXPECT_EQ(picture(s, shading, LightingPath::simd, Isa::sse2, 3), first);
  }
}

TEST(DynamicEnvironment, Validation) {
  Scene s = mirror_in_room(16);
  s.materials.back().environment.resolution = 0;
  Status st = validate_scene(s);
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(st.field(), "materials[12].environment.resolution");
  s = mirror_in_room(16);
  s.materials.back().environment.mode = EnvironmentMode::sphere;
  st = validate_scene(s);
  EXPECT_EQ(st.field(), "materials[12].environment.dynamic");
  s = mirror_in_room(4096);
  RenderOptions o = test::gl_options();
  o.memory_budget_bytes = 64u << 20;  // six 4096^2 faces take 384 MiB
  st = check_render(s, o, 64, 64);
  EXPECT_EQ(st.code(), ErrorCode::out_of_memory) << st.message();
}

}  // namespace
}  // namespace facet
