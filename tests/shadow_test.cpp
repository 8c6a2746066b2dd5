// Shadows (issue 17): ray-cast shadows through Embree against the analytic shadow of a sphere on
// a plane, the shadowed light's terms (ambient kept, diffuse and specular blocked), the object
// flags, determinism over threads, and the refusals (methods not implemented yet, Gouraud).
#include <cmath>
#include <cstring>

#include <Eigen/Dense>

#include "render_support.hpp"

namespace facet {
namespace {

using test::Canvas;

constexpr int kSize = 96;
const Vec3 kCentre(0.0f, 1.5f, 0.0f);
constexpr float kRadius = 1.0f;

// A plane seen from above, a sphere over it, one directional light at 45 degrees that casts
// ray-cast shadows; Phong, no specular.
Scene sphere_over_plane() {
  Scene s;
  s.meshes.push_back({"plane", make_plane(8.0f, 8.0f, 4)});
  s.meshes.push_back({"ball", make_uv_sphere(kRadius, 96, 48)});
  Material m;
  m.ambient = Color3(1, 1, 1);
  m.diffuse = Color3(1, 1, 1);
  m.specular = Color3(0, 0, 0);
  s.materials.push_back(m);
  s.objects.push_back(Instance{0, 0});
  Instance ball{1, 0};
  ball.model.block<3, 1>(0, 3) = kCentre;
  s.objects.push_back(ball);
  Light sun;
  sun.type = LightType::directional;
  sun.direction = Vec3(1, -1, 0).normalized();
  sun.diffuse = Color3(0.8f, 0.8f, 0.8f);
  sun.specular = Color3(0, 0, 0);
  sun.shadow.method = ShadowMethod::raycast;
  s.lights.push_back(sun);
  s.global_ambient = Color3(0.2f, 0.2f, 0.2f);
  s.camera.eye = Vec3(0, 12, 0);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.up = Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 40.0f;
  s.camera.near = 1.0f;
  s.camera.far = 30.0f;
  return s;
}

std::vector<std::uint8_t> render(const Scene& s, int threads = 0, LightingPath path = LightingPath::simd,
                                 Isa isa = Isa::best, Status* status = nullptr,
                                 ShadingMode shading = ShadingMode::phong) {
  Canvas c(kSize, kSize);
  RenderOptions o = test::gl_options();
  o.shading = shading;
  o.threads = threads;
  o.path = path;
  o.isa = isa;
  Renderer r;
  const Status st = r.render(s, o, c.view());
  if (status) *status = st;
  else EXPECT_TRUE(st.ok()) << st.message();
  std::vector<std::uint8_t> out(static_cast<std::size_t>(kSize * kSize * 4));
  for (int y = 0; y < kSize; ++y) std::memcpy(&out[static_cast<std::size_t>(y * kSize * 4)], c.row(y), kSize * 4);
  return out;
}

// Where the view ray through pixel (x, y)'s centre meets the plane y = 0, and how far (in world
// units, measured on the plane) that point is from the edge of the sphere's exact shadow
// (negative inside), and whether the sphere hides it from the camera.
struct PlanePoint {
  Vec3 p;
  double shadow_margin;
  bool behind_sphere;
};
PlanePoint plane_point(const Scene& s, int x, int y) {
  const Eigen::Matrix4d vp = (projection_matrix(s.camera, 1.0f) * view_matrix(s.camera)).cast<double>();
  const Eigen::Matrix4d inv = vp.inverse();
  const double nx = 2.0 * (x + 0.5) / kSize - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / kSize;
  Eigen::Vector4d a = inv * Eigen::Vector4d(nx, ny, -1, 1), b = inv * Eigen::Vector4d(nx, ny, 1, 1);
  const Eigen::Vector3d o = a.head<3>() / a.w(), e = b.head<3>() / b.w();
  const Eigen::Vector3d d = (e - o).normalized();
  const double t = -o.y() / d.y();
  const Eigen::Vector3d p = o + t * d;
  const Eigen::Vector3d c = kCentre.cast<double>();
  // Shadow: the line from p towards the light passes within kRadius of the centre. Its distance
  // to the centre minus the radius, scaled to the plane (the shadow is stretched by 1 / cos 45).
  const Light& light = s.lights[0];
  const bool directional = light.type == LightType::directional;
  const Eigen::Vector3d to_light = directional ? Eigen::Vector3d(-light.direction.cast<double>().normalized())
                                               : Eigen::Vector3d((light.position.cast<double>() - p).normalized());
  const double reach = directional ? 1e300 : (light.position.cast<double>() - p).norm();
  const Eigen::Vector3d w = c - p;
  const double along = std::min(w.dot(to_light), reach);
  const double dist = along > 0 ? (w - along * to_light).norm() : w.norm();
  const Eigen::Vector3d wc = c - o;
  const double view_dist = (wc - wc.dot(d) * d).norm();
  return {p.cast<float>(), (dist - kRadius) * std::sqrt(2.0), view_dist < kRadius + 0.05};
}

// Renders `s` with its light's shadows, without them, and with the light off, and compares each
// plane pixel with the sphere's exact shadow: more than `margin` (world units on the plane)
// inside it the pixel must be the light-off one, more than `margin` outside it the unshadowed
// one, byte for byte; in between either (`hard`), or (a filtered map) anything between the two.
// Pixels the light does not reach (lit = dark) are skipped. Returns the pixels checked in shadow
// and in light.
std::pair<int, int> compare_with_exact_shadow(const Scene& s, double margin, bool hard = true) {
  const std::vector<std::uint8_t> shadowed = render(s);
  Scene unshadowed_scene = s;
  unshadowed_scene.lights[0].shadow.method = ShadowMethod::none;
  const std::vector<std::uint8_t> lit = render(unshadowed_scene);
  Scene dark_scene = s;
  dark_scene.lights[0].enabled = false;
  const std::vector<std::uint8_t> dark = render(dark_scene);
  int in_shadow = 0, in_light = 0, wrong = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const PlanePoint pp = plane_point(s, x, y);
      if (pp.behind_sphere || std::abs(pp.p.x()) > 3.9f || std::abs(pp.p.z()) > 3.9f) continue;
      const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
      if (std::memcmp(&lit[at], &dark[at], 3) == 0) continue;  // the light does not reach it
      const bool equals_dark = std::memcmp(&shadowed[at], &dark[at], 3) == 0;
      const bool equals_lit = std::memcmp(&shadowed[at], &lit[at], 3) == 0;
      if (pp.shadow_margin < -margin) {
        ++in_shadow;
        if (!equals_dark && ++wrong <= 5) ADD_FAILURE() << "lit inside the shadow at pixel " << x << ", " << y;
      } else if (pp.shadow_margin > margin) {
        ++in_light;
        if (!equals_lit && ++wrong <= 5) ADD_FAILURE() << "shadowed outside the shadow at pixel " << x << ", " << y;
      } else if (hard) {
        EXPECT_TRUE(equals_dark || equals_lit) << "a pixel is either lit or in shadow: " << x << ", " << y;
      } else {
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(shadowed[at + c], std::min(dark[at + c], lit[at + c]) - 1) << x << ", " << y;
          EXPECT_LE(shadowed[at + c], std::max(dark[at + c], lit[at + c]) + 1) << x << ", " << y;
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  return {in_shadow, in_light};
}

TEST(Shadows, RaycastMatchesTheSpheresExactShadow) {
  // A pixel's footprint on the plane, with room for the view's slant.
  const auto [in_shadow, in_light] = compare_with_exact_shadow(sphere_over_plane(), 8.0 / kSize * 1.2);
  EXPECT_GT(in_shadow, 200);
  EXPECT_GT(in_light, 2000);
}

// The same with a spot light above and beside the sphere: its cone covers part of the plane;
// outside the cone no ray is cast (the light gives nothing there), inside the shadow is exact.
TEST(Shadows, SpotLightMatchesTheSpheresExactShadow) {
  Scene s = sphere_over_plane();
  Light& spot = s.lights[0];
  spot.type = LightType::spot;
  spot.position = Vec3(-2.0f, 4.5f, 0.0f);
  spot.direction = Vec3(0.8f, -1.0f, 0.0f).normalized();
  spot.spot_shape = SpotShape::smooth_cone;
  spot.spot_inner_deg = 30.0f;
  spot.spot_outer_deg = 40.0f;
  // The point light's shadow stretches more on the plane.
  const auto [in_shadow, in_light] = compare_with_exact_shadow(s, 8.0 / kSize * 2.0);
  EXPECT_GT(in_shadow, 100);
  EXPECT_GT(in_light, 500);
  // Outside the cone the image is the unshadowed one: skipping rays there changes no byte.
  Scene unshadowed = s;
  unshadowed.lights[0].shadow.method = ShadowMethod::none;
  EXPECT_EQ(std::memcmp(render(s).data(), render(unshadowed).data(), 4), 0);
}

// The same bytes for 1, 2, 3 and 8 threads; the lighting paths differ in the last bit of their
// arithmetic (within a step), not in what is shadowed.
void expect_same_for_threads_and_paths(const Scene& s) {
  const std::vector<std::uint8_t> one = render(s, 1);
  EXPECT_EQ(render(s, 2), one);
  EXPECT_EQ(render(s, 3), one);
  EXPECT_EQ(render(s, 8), one);
  for (const LightingPath path : {LightingPath::reference, LightingPath::scalar}) {
    const std::vector<std::uint8_t> other = render(s, 2, path);
    int far = 0;
    for (std::size_t i = 0; i < one.size(); ++i) far += std::abs(int(one[i]) - int(other[i])) > 1 ? 1 : 0;
    EXPECT_EQ(far, 0) << "path " << int(path);
  }
}

// Nothing casting, or nothing receiving, gives the unshadowed image bit for bit: every point sees
// the light, and visibility 1 changes no bit.
void expect_unshadowed_without_casters_or_receivers(const Scene& s) {
  Scene none = s;
  none.lights[0].shadow.method = ShadowMethod::none;
  const std::vector<std::uint8_t> unshadowed = render(none);
  Scene no_casters = s;
  for (Instance& i : no_casters.objects) i.cast_shadows = false;
  EXPECT_EQ(render(no_casters), unshadowed);
  Scene no_receivers = s;
  for (Instance& i : no_receivers.objects) i.receive_shadows = false;
  EXPECT_EQ(render(no_receivers), unshadowed);
}

TEST(Shadows, SameBytesForEveryThreadCountAndPath) { expect_same_for_threads_and_paths(sphere_over_plane()); }

TEST(Shadows, ObjectFlagsAndLitPointsAreExact) {
  const Scene s = sphere_over_plane();
  expect_unshadowed_without_casters_or_receivers(s);
  // Only the sphere casts and only the plane receives: still the shadow on the plane.
  Scene split = s;
  split.objects[0].cast_shadows = false;
  split.objects[1].receive_shadows = false;
  EXPECT_EQ(render(split), render(s));
}

TEST(Shadows, AmbientTermIsNotBlocked) {
  Scene s = sphere_over_plane();
  s.lights[0].ambient = Color3(0.3f, 0.3f, 0.3f);
  const std::vector<std::uint8_t> img = render(s);
  // A pixel inside the shadow (world (2.2, 0, 0)) keeps the light's ambient term: brighter than
  // the scene's ambient alone (0.2 -> 51), equal to ambient + light ambient (0.5 -> 128).
  int found = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const PlanePoint pp = plane_point(s, x, y);
      if (pp.behind_sphere || pp.shadow_margin > -0.3) continue;
      const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
      EXPECT_NEAR(img[at], 128, 1) << x << ", " << y;
      ++found;
    }
  }
  EXPECT_GT(found, 50);
}

TEST(Shadows, RefusedWhereNotDrawnYet) {
  Scene s = sphere_over_plane();
  Canvas c(16, 16);
  RenderOptions o = test::gl_options();
  o.shading = ShadingMode::gouraud;
  Renderer r;
  // Flat and Gouraud shadows sum sub-frames: materials whose colour is not linear in the lighting
  // are refused there (Phong draws them).
  s.materials[0].blend = BlendMode::add;
  Status st = r.render(s, o, c.view());
  EXPECT_EQ(st.code(), ErrorCode::unsupported);
  EXPECT_NE(st.message().find("materials[0].blend"), std::string::npos) << st.message();
  EXPECT_TRUE(c.untouched());
  o.shading = ShadingMode::phong;
  EXPECT_TRUE(r.render(s, o, c.view()).ok());
  s.materials[0].blend = BlendMode::opaque;
  // At most kMaxShadowedLights lights cast shadows.
  s.lights.assign(kMaxShadowedLights + 1, s.lights[0]);
  for (Light& l : s.lights) l.shadow.method = ShadowMethod::raycast;
  Canvas fresh(16, 16);
  st = r.render(s, o, fresh.view());
  EXPECT_EQ(st.code(), ErrorCode::invalid_argument);
  EXPECT_NE(st.message().find("at most"), std::string::npos) << st.message();
  EXPECT_TRUE(fresh.untouched());
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// Casters with huge, NaN and infinite coordinates, and degenerate triangles, some of them drawn
// (clipped) so that shaded points lie beyond what Embree accepts (|coordinate| > 1.8e18: its
// assertion aborted the process before such rays were left uncast): no crash, no hang, the same
// bytes on every thread count, ray-cast and with a map.
TEST(Shadows, HostileCastersAreHarmless) {
  Scene s = sphere_over_plane();
  Mesh junk;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  junk.positions = {Vec3(0, 2, 0),     Vec3(1e30f, 2, 0), Vec3(0, 2, 1e30f), Vec3(nan, 2, 0), Vec3(1, 2, 1),
                    Vec3(inf, 2, -inf), Vec3(0.5f, 2, 0.5f), Vec3(0.5f, 2, 0.5f), Vec3(-1e30f, -1e30f, 3)};
  junk.triangles = {{0, 1, 2}, {0, 3, 4}, {5, 4, 0}, {6, 7, 0}, {8, 1, 2}, {6, 6, 6}};
  junk.normals.assign(junk.positions.size(), Vec3(0, 1, 0));
  s.meshes.push_back({"junk", junk});
  s.objects.push_back(Instance{2, 0});
  for (const ShadowMethod method : {ShadowMethod::raycast, ShadowMethod::map, ShadowMethod::volume}) {
    s.lights[0].shadow.method = method;  // a map's fit then spans 1e30: it shows nothing, harmlessly
    Status st;
    const std::vector<std::uint8_t> one = render(s, 1, LightingPath::simd, Isa::best, &st);
    ASSERT_TRUE(st.ok()) << st.message();  // such meshes are valid: their bad triangles are dropped
    EXPECT_EQ(render(s, 2), one);
    EXPECT_EQ(render(s, 8), one);
    for (const LightingPath path : {LightingPath::reference, LightingPath::scalar}) {
      render(s, 2, path, Isa::best, &st);
      EXPECT_TRUE(st.ok()) << st.message();
    }
  }
}

}  // namespace
}  // namespace facet

#include "shadow/raycast.hpp"

namespace facet {
namespace {

// The caster's queries on their own: points and directions beyond what Embree accepts (it asserts
// and aborts on rays with coordinates past 1.8e18) are not cast and count as lit; a point under a
// square is shadowed, one beside it is not; a stray far vertex does not change the radius.
TEST(Shadows, RayCasterQueriesAreSafe) {
  Scene s;
  Mesh square;
  square.positions = {Vec3(-1, 1, -1), Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(-1, 1, 1), Vec3(1e30f, 0, 0)};
  square.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 4, 0}};
  square.normals.assign(square.positions.size(), Vec3(0, 1, 0));
  s.meshes.push_back({"square", square});
  s.materials.push_back(Material{});
  s.objects.push_back(Instance{0, 0});
  shadow::RayCaster caster;
  ASSERT_TRUE(caster.build(s, Eigen::Matrix4d::Identity()).ok());
  EXPECT_EQ(caster.triangle_count(), 3u);
  EXPECT_NEAR(caster.radius(), std::sqrt(2.0f), 1e-5f);  // the flat square's half diagonal: the 1e30 vertex is left out
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float px[] = {0, 3, 1e30f, 0, nan, 0, 0}, py[] = {0, 0, 0, -1e25f, 0, inf, 0}, pz[] = {0, 0, 0, 0, 0, 0, 1e19f};
  const float nx[7] = {}, ny[] = {1, 1, 1, 1, 1, 1, 1}, nz[7] = {};
  float visible[7];
  shadow::RayCaster::Target up;
  up.directional = true, up.y = 1.0f;
  caster.visibility(up, 0.0f, 7, px, py, pz, nx, ny, nz, 1, visible);
  EXPECT_EQ(visible[0], 0.0f);  // under the square
  EXPECT_EQ(visible[1], 1.0f);  // beside it
  for (int i = 2; i < 7; ++i) EXPECT_EQ(visible[i], 1.0f) << "point " << i << " is not castable: lit";
  shadow::RayCaster::Target lamp;  // a point light above the square, and one at 1e30
  lamp.y = 5.0f;
  caster.visibility(lamp, 0.0f, 2, px, py, pz, nx, ny, nz, 1, visible);
  EXPECT_EQ(visible[0], 0.0f);
  EXPECT_EQ(visible[1], 1.0f);
  lamp.y = 1e30f;
  caster.visibility(lamp, 0.0f, 2, px, py, pz, nx, ny, nz, 1, visible);
  EXPECT_EQ(visible[0], 1.0f);  // the segment's direction is beyond Embree's range: not cast
}

}  // namespace
}  // namespace facet

// Shadow maps (shadow/map.hpp): the same sphere over a plane with a map for a directional, a spot
// and a point light (cube), each filter, against the sphere's exact shadow; determinism; what
// happens with nothing to cast; and the stability cases of issue 17, each named.
namespace facet {
namespace {

Scene with_map(Scene s, ShadowFilter filter = ShadowFilter::pcf3x3, int resolution = 2048) {
  for (Light& l : s.lights) {
    l.shadow.method = ShadowMethod::map;
    l.shadow.filter = filter;
    l.shadow.resolution = resolution;
  }
  return s;
}

Scene with_volume(Scene s) {
  for (Light& l : s.lights) l.shadow.method = ShadowMethod::volume;
  return s;
}

Scene spot_over_sphere() {
  Scene s = sphere_over_plane();
  Light& spot = s.lights[0];
  spot.type = LightType::spot;
  spot.position = Vec3(-2.0f, 4.5f, 0.0f);
  spot.direction = Vec3(0.8f, -1.0f, 0.0f).normalized();
  spot.spot_shape = SpotShape::smooth_cone;
  spot.spot_inner_deg = 30.0f;
  spot.spot_outer_deg = 40.0f;
  return s;
}

Scene point_over_sphere() {
  Scene s = sphere_over_plane();
  Light& lamp = s.lights[0];
  lamp.type = LightType::point;
  lamp.position = Vec3(-2.5f, 4.0f, 0.3f);
  return s;
}

// The world size of one of the map's texels on the plane near the shadow, a generous bound for
// these scenes (the directional map spans at most the plane's 8 x 8 units; the spot and cube faces
// are at most 7 units from the shadow, with a field of view of at most 2 x 45 degrees, widened).
double texel_bound(const Light& l) {
  const double r = l.shadow.resolution;
  return l.type == LightType::directional ? 11.4 / r : 2.0 * 7.0 * 1.1 / r;
}

// How far the map's shadow edge may lie from the exact one on the plane: a pixel's footprint, and
// the filter's reach and the bias (normal, and the slope term at 45 degrees), in texels, stretched
// by the light's slant on the plane (at most 2x here).
double map_margin(const Light& l) {
  const double radius = shadow_filter_width(l.shadow.filter) / 2.0 + 0.5;
  const double reach = radius * (1.0 + l.shadow.bias.normal + l.shadow.bias.slope + l.shadow.bias.constant);
  return 8.0 / kSize * 1.2 + 2.0 * reach * texel_bound(l);
}

TEST(ShadowMaps, MatchTheSpheresExactShadow) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    for (const ShadowFilter filter : {ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5}) {
      for (const int resolution : {256, 2048}) {
        const Scene s = with_map(base, filter, resolution);
        SCOPED_TRACE(std::to_string(static_cast<int>(s.lights[0].type)) + " " + to_string(filter) + " " + std::to_string(resolution));
        const auto [in_shadow, in_light] = compare_with_exact_shadow(s, map_margin(s.lights[0]), filter == ShadowFilter::none);
        EXPECT_GT(in_shadow, resolution == 256 ? 20 : 60);
        EXPECT_GT(in_light, 500);
      }
    }
  }
}

TEST(ShadowMaps, SameBytesForEveryThreadCountAndPath) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    expect_same_for_threads_and_paths(with_map(base));
  }
}

TEST(ShadowMaps, NothingToCastIsTheUnshadowedImage) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    expect_unshadowed_without_casters_or_receivers(with_map(base));
  }
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// Renders `s` with shadow maps and with ray-cast shadows (the exact reference) and compares them:
// every pixel farther than `band` pixels from a ray-cast shadow edge (a pixel whose ray-cast
// visibility differs from a neighbour's) has the ray-cast image's bytes. Returns the pixels in
// ray-cast shadow and how many pixels were compared.
struct Agreement {
  int shadowed = 0, compared = 0, wrong = 0;
};
Agreement compare_with_raycast(const Scene& s, int band, ShadowFilter filter = ShadowFilter::pcf3x3,
                               ShadowMethod method = ShadowMethod::map) {
  Scene ray = s, map = method == ShadowMethod::volume ? with_volume(s) : with_map(s, filter), none = s;
  for (Light& l : ray.lights) l.shadow.method = ShadowMethod::raycast;
  for (Light& l : none.lights) l.shadow.method = ShadowMethod::none;
  const std::vector<std::uint8_t> exact = render(ray), approx = render(map), unshadowed = render(none);
  auto in_shadow = [&](int x, int y) {
    const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
    return std::memcmp(&exact[at], &unshadowed[at], 3) != 0;
  };
  Agreement a;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool here = in_shadow(x, y);
      a.shadowed += here ? 1 : 0;
      bool near_edge = false;
      for (int dy = -band; dy <= band && !near_edge; ++dy) {
        for (int dx = -band; dx <= band; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u >= 0 && v >= 0 && u < kSize && v < kSize && in_shadow(u, v) != here) {
            near_edge = true;
            break;
          }
        }
      }
      if (near_edge) continue;
      ++a.compared;
      const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
      if (std::memcmp(&exact[at], &approx[at], 3) != 0 && ++a.wrong <= 5) {
        ADD_FAILURE() << "pixel " << x << ", " << y << " (ray-cast " << (here ? "shadowed" : "lit") << "): red " << int(exact[at])
                      << " ray-cast, " << int(approx[at]) << " this method, " << int(unshadowed[at]) << " unshadowed";
      }
    }
  }
  EXPECT_EQ(a.wrong, 0);
  return a;
}

// A plane alone, casting and receiving, under a light at `elevation` degrees: no pixel may shadow
// itself (the image is the unshadowed one, byte for byte), with every filter.
TEST(ShadowMaps, NoAcneOnALitPlaneFrom2To89Degrees) {
  Scene s = sphere_over_plane();
  s.objects.pop_back();  // the plane alone
  for (const double elevation : {2.0, 5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
    const double e = elevation * 3.14159265358979 / 180.0;
    for (const ShadowFilter filter : {ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5}) {
      Scene sun = s;
      sun.lights[0].direction = Vec3(float(-std::cos(e) * 0.8), float(-std::sin(e)), float(-std::cos(e) * 0.6));
      Scene none = sun;
      none.lights[0].shadow.method = ShadowMethod::none;
      // The spot light at the same elevation seen from the plane's centre, 6 units away.
      Scene spot = spot_over_sphere();
      spot.objects.pop_back();
      spot.lights[0].spot_outer_deg = 60.0f;
      spot.lights[0].position = Vec3(float(6 * std::cos(e)), float(6 * std::sin(e)), 0.0f);
      spot.lights[0].direction = -spot.lights[0].position.normalized();
      Scene spot_none = spot;
      spot_none.lights[0].shadow.method = ShadowMethod::none;
      SCOPED_TRACE(std::to_string(elevation) + " degrees, " + to_string(filter));
      EXPECT_EQ(render(with_map(sun, filter)), render(none));
      EXPECT_EQ(render(with_map(spot, filter)), render(spot_none));
      if (filter == ShadowFilter::none) {  // volumes: the plane is its own front cap
        EXPECT_EQ(render(with_volume(sun)), render(none)) << "volume";
        EXPECT_EQ(render(with_volume(spot)), render(spot_none)) << "volume";
      }
    }
  }
  // A point light just over the plane lights it at every elevation from 90 degrees (below it) to
  // a few degrees (the plane's corners); a cube map of six faces.
  Scene lamp = point_over_sphere();
  lamp.objects.pop_back();
  lamp.lights[0].position = Vec3(0.3f, 0.25f, -0.2f);
  Scene lamp_none = lamp;
  lamp_none.lights[0].shadow.method = ShadowMethod::none;
  for (const ShadowFilter filter : {ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5}) {
    EXPECT_EQ(render(with_map(lamp, filter)), render(lamp_none)) << to_string(filter);
  }
  EXPECT_EQ(render(with_volume(lamp)), render(lamp_none)) << "volume";
}

// A ray from the camera through pixel (x, y)'s centre: origin and unit direction.
std::pair<Eigen::Vector3d, Eigen::Vector3d> view_ray(const Scene& s, int x, int y) {
  const Eigen::Matrix4d inv = (projection_matrix(s.camera, 1.0f) * view_matrix(s.camera)).cast<double>().inverse();
  const double nx = 2.0 * (x + 0.5) / kSize - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / kSize;
  const Eigen::Vector4d a = inv * Eigen::Vector4d(nx, ny, -1, 1), b = inv * Eigen::Vector4d(nx, ny, 1, 1);
  const Eigen::Vector3d o = a.head<3>() / a.w();
  return {o, (b.head<3>() / b.w() - o).normalized()};
}

// Peter-panning: a unit cube standing on the plane, lit at 45 degrees with a 2048^2 map; the
// shadow must reach the cube's foot: every plane pixel seen beside the cube's shadowed side, more
// than one pixel's footprint from the contact line and inside the exact shadow, is in shadow.
TEST(ShadowMaps, ContactShadowGapAtMostOnePixel) {
  const ShadowFilter filters[] = {ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5};
  for (int run = 0; run < 5; ++run) {  // each filter's map, then volumes
    const bool volume = run == 4;
    const ShadowFilter filter = volume ? ShadowFilter::none : filters[run];
    Scene s = sphere_over_plane();
    s.meshes[1] = {"cube", make_cube(1.0f, 1)};
    s.objects[1].model = Mat4::Identity();
    s.objects[1].model(1, 3) = 0.5f;  // standing on the plane: x, z in [-0.5, 0.5], y in [0, 1]
    s.lights[0].direction = Vec3(-1, -1, 0).normalized();  // from +x: the shadow lies over x in [-1.5, -0.5]
    s.camera.eye = Vec3(-4.0f, 3.0f, 1.5f);
    s.camera.target = Vec3(-0.8f, 0.0f, 0.0f);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.vertical_fov_deg = 30.0f;
    Scene dark = s;
    dark.lights[0].enabled = false;
    const std::vector<std::uint8_t> img = render(volume ? with_volume(s) : with_map(s, filter)), off = render(dark);
    int checked = 0, gaps = 0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        auto hit = [&](int px, int py) {
          const auto [o, d] = view_ray(s, px, py);
          return Eigen::Vector3d(o + (-o.y() / d.y()) * d);
        };
        const Eigen::Vector3d p = hit(x, y);
        // Seen beside the cube's shadowed side (not through the cube: the view ray stays in x < -0.5).
        if (!(p.x() < -0.5 && p.x() > -1.45 && std::abs(p.z()) < 0.45)) continue;
        const double footprint = std::max((hit(x + 1, y) - p).norm(), (hit(x, y + 1) - p).norm());
        if (p.x() > -0.5 - footprint) continue;  // within a pixel of the contact line
        const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
        ++checked;
        if (std::memcmp(&img[at], &off[at], 3) != 0 && ++gaps <= 5) {
          ADD_FAILURE() << (volume ? "volume" : to_string(filter)) << ": lit at pixel " << x << ", " << y << ", plane x " << p.x();
        }
      }
    }
    EXPECT_GT(checked, 100);
    EXPECT_EQ(gaps, 0) << (volume ? "volume" : to_string(filter));
  }
}

// A point light inside the bounding box of a caster: a floor and a ceiling in one mesh, the light
// between them over a sphere; the cube map's near plane cannot sit at the box.
TEST(ShadowMaps, LightInsideACastersBoundingBox) {
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::volume}) {
    SCOPED_TRACE(to_string(method));
    Scene s = point_over_sphere();
    Mesh room = make_plane(8.0f, 8.0f, 4);
    const std::size_t n = room.positions.size();
    for (std::size_t i = 0; i < n; ++i) {  // the ceiling: the floor raised to y = 4, facing down
      room.positions.push_back(room.positions[i] + Vec3(0, 4, 0));
      room.normals.push_back(Vec3(0, -1, 0));
      if (!room.uvs.empty()) room.uvs.push_back(room.uvs[i]);
    }
    const std::size_t t = room.triangles.size();
    for (std::size_t i = 0; i < t; ++i) {
      const auto& tri = room.triangles[i];
      room.triangles.push_back({static_cast<std::uint32_t>(tri[0] + n), static_cast<std::uint32_t>(tri[2] + n),
                                static_cast<std::uint32_t>(tri[1] + n)});
    }
    s.meshes[0] = {"room", room};
    s.lights[0].position = Vec3(-1.0f, 3.0f, 0.2f);
    s.camera.eye = Vec3(0, 3.5f, 6.0f);  // between floor and ceiling, looking at the floor
    s.camera.target = Vec3(0, 0, 0);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.vertical_fov_deg = 60.0f;
    const Agreement a = compare_with_raycast(s, 2, ShadowFilter::pcf3x3, method);
    EXPECT_GT(a.shadowed, 100);
    EXPECT_GT(a.compared, kSize * kSize / 2);
  }
}

// A spot light whose nearest caster lies at the map's near plane: a small square just in front of
// the light throws a large shadow on the plane.
TEST(ShadowMaps, SpotLightAtTheNearPlane) {
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::volume}) {
    SCOPED_TRACE(to_string(method));
    Scene s = spot_over_sphere();
    Mesh square = make_plane(0.1f, 0.1f, 1);
    s.meshes[1] = {"square", square};
    Light& spot = s.lights[0];
    spot.position = Vec3(0.0f, 5.0f, 0.0f);
    spot.direction = Vec3(0.0f, -1.0f, 0.0f);
    s.objects[1].model = Mat4::Identity();
    s.objects[1].model(1, 3) = 4.99f;  // 1 cm under the light: the map's near plane
    const Agreement a = compare_with_raycast(s, 2, ShadowFilter::pcf3x3, method);
    EXPECT_GT(a.shadowed, 300);
  }
}

// A directional light along the camera's up vector (and along the world's y axis, the map's
// default up): the map's orientation must not degenerate.
TEST(ShadowMaps, DirectionalLightAlongTheCamerasUp) {
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::volume}) {
    SCOPED_TRACE(to_string(method));
    Scene s = sphere_over_plane();
    s.camera.eye = Vec3(0.0f, 6.0f, 9.0f);
    s.camera.up = Vec3(0, 1, 0);
    s.lights[0].direction = Vec3(0, -1, 0);
    const Agreement a = compare_with_raycast(s, 2, ShadowFilter::pcf3x3, method);
    EXPECT_GT(a.shadowed, 100);
  }
}

// A point light whose shadow falls exactly along the border of two cube faces, and along a corner
// of three: no seam (the faces are wider than 90 degrees by the filter's reach).
TEST(ShadowMaps, PointLightOnACubeFaceBorder) {
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::volume}) {
    SCOPED_TRACE(to_string(method));
    for (const Vec3& way : {Vec3(1, -1, 0), Vec3(1, -1, 1), Vec3(0, -1, 1)}) {
      Scene s = point_over_sphere();
      s.lights[0].position = Vec3(-1.5f, 3.5f, -1.0f);
      s.objects[1].model.block<3, 1>(0, 3) = s.lights[0].position + 1.6f * way.normalized();
      s.objects[1].model.block<3, 3>(0, 0) = Eigen::Matrix3f::Identity() * 0.5f;
      const Agreement a = compare_with_raycast(s, 2, ShadowFilter::pcf3x3, method);
      EXPECT_GT(a.shadowed, 30) << way.transpose();
    }
  }
}

// A scene of zero extent: every caster vertex at one point. Nothing can be drawn into a map, and
// nothing is shadowed; no division by a zero extent.
TEST(ShadowMaps, ZeroExtentScene) {
  for (const Scene& any : {sphere_over_plane(), spot_over_sphere(), point_over_sphere(), with_volume(sphere_over_plane()),
                           with_volume(spot_over_sphere()), with_volume(point_over_sphere())}) {
    Scene s = any.lights[0].shadow.method == ShadowMethod::volume ? any : with_map(any);
    for (Vec3& p : s.meshes[1].mesh.positions) p = Vec3(0.0f, 0.0f, 0.0f);
    s.objects[0].cast_shadows = false;
    Scene none = s;
    none.lights[0].shadow.method = ShadowMethod::none;
    EXPECT_EQ(render(s), render(none));
    Scene all = s;  // the point alone, at the light itself
    all.objects[1].model.block<3, 1>(0, 3) = all.lights[0].type == LightType::directional ? Vec3(0, 0, 0) : all.lights[0].position;
    Scene all_none = all;
    all_none.lights[0].shadow.method = ShadowMethod::none;
    EXPECT_EQ(render(all), render(all_none));
  }
}

// A million caster triangles (a finely divided sphere): the map draws them through the same tile
// pipeline; the shadow agrees with the ray-cast one.
TEST(ShadowMaps, AMillionCasters) {
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::volume}) {
    SCOPED_TRACE(to_string(method));
    Scene s = sphere_over_plane();
    s.meshes[1] = {"ball", make_uv_sphere(kRadius, 1000, 500)};
    ASSERT_GE(s.meshes[1].mesh.triangle_count(), 990000u);
    const Agreement a = compare_with_raycast(s, 2, ShadowFilter::pcf3x3, method);
    EXPECT_GT(a.shadowed, 200);
  }
}

// Casters entirely outside the view still cast into it: the directional map is fitted to the
// casters within the view's footprint across the light, not to the view.
TEST(ShadowMaps, CastersOutsideTheView) {
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::volume}) {
    SCOPED_TRACE(to_string(method));
    for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
      Scene s = base;
      s.camera.target = Vec3(1.5f, 0.0f, 0.0f);
      s.camera.eye = Vec3(1.5f, 4.0f, 0.0f);  // sees x in about [0, 3]: the sphere at x = 0 is outside
      s.objects[1].model.block<3, 1>(0, 3) = Vec3(-0.6f, 2.0f, 0.0f);
      const Agreement a = compare_with_raycast(s, 2, ShadowFilter::pcf3x3, method);
      EXPECT_GT(a.shadowed, 20);
    }
  }
}

}  // namespace
}  // namespace facet

#include <random>

#include "raster/tile_raster.hpp"
#include "shadow/map.hpp"

namespace facet {
namespace {

// The SIMD shadow-map lookup of every ISA against its scalar twin, bit for bit: the three kinds
// of map, every filter, random depths, and points anywhere (outside the map, behind the light,
// on face borders, with zero, NaN and infinite coordinates and normals), stride 1 and 3.
TEST(ShadowMaps, SimdLookupIsTheScalarOneBitForBit) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> coord(-6.0f, 6.0f), unit(0.0f, 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  shadow::CasterBounds casters;
  casters.lo = {Eigen::Vector3d(-4, 0, -4), Eigen::Vector3d(-1, 0.5, -1)};
  casters.hi = {Eigen::Vector3d(4, 0, 4), Eigen::Vector3d(1, 2.5, 1)};
  const Scene base = sphere_over_plane();
  const Eigen::Matrix4d view = view_matrix(base.camera).cast<double>();
  const Eigen::Matrix4d projection = projection_matrix(base.camera, 1.0f).cast<double>();
  int compared = 0;
  for (const Scene& s : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    for (const ShadowFilter filter : {ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5}) {
      Light light = s.lights[0];
      light.shadow.method = ShadowMethod::map;
      light.shadow.filter = filter;
      light.shadow.resolution = 64;
      light.shadow.bias.slope = 0.5f;  // every bias term in play
      light.shadow.bias.constant = 0.25f;
      shadow::ShadowMap map;
      map.plan(light, casters, view, projection);
      ASSERT_FALSE(map.empty());
      for (int f = 0; f < map.face_count(); ++f) {
        const DepthView d = map.depth_view(f);
        for (int y = 0; y < d.height; ++y) {
          for (int x = 0; x < d.width; ++x) {  // blocks of 8 x 8 texels: casters near the light or none
            std::mt19937 block(static_cast<unsigned>(f * 4096 + (y / 8) * 64 + x / 8));
            d.data[y * d.width + x] = block() % 3 == 0 ? 1.0f : 0.1f * unit(rng);
          }
        }
      }
      constexpr std::size_t kPoints = 1000;
      std::vector<float> p(6 * kPoints);
      for (std::size_t i = 0; i < kPoints; ++i) {
        const Eigen::Vector4d world(coord(rng), coord(rng) * 0.5f + 1.5f, coord(rng), 1.0);
        const Eigen::Vector4d eye = view * world;
        for (int c = 0; c < 3; ++c) p[6 * i + c] = static_cast<float>(eye[c]), p[6 * i + 3 + c] = coord(rng);
      }
      const float odd[][6] = {{0, 0, 0, 0, 0, 0},  {nan, 0, -5, 0, 1, 0}, {0, inf, -5, 0, 1, 0}, {0, 0, -5, nan, 1, 0},
                              {1e20f, 0, -5, 0, 1, 0}, {0, 0, -5, 1e20f, 0, 0}, {0, 0, 5, 0, 1, 0}};
      for (std::size_t k = 0; k < std::size(odd); ++k) std::copy_n(odd[k], 6, &p[6 * k]);
      auto run = [&](shadow::MapVisibilityFunction kernel, bool soa) {
        map.set_kernel(kernel);
        std::vector<float> out(kPoints);
        if (soa) {
          std::vector<float> streams(6 * kPoints);
          for (std::size_t i = 0; i < kPoints; ++i) {
            for (int c = 0; c < 6; ++c) streams[static_cast<std::size_t>(c) * kPoints + i] = p[6 * i + c];
          }
          const float* q = streams.data();
          map.visibility(kPoints, q, q + kPoints, q + 2 * kPoints, q + 3 * kPoints, q + 4 * kPoints, q + 5 * kPoints, 1,
                         out.data());
        } else {
          std::vector<float> xyz(3 * kPoints), nrm(3 * kPoints);
          for (std::size_t i = 0; i < kPoints; ++i) {
            for (int c = 0; c < 3; ++c) xyz[3 * i + c] = p[6 * i + c], nrm[3 * i + c] = p[6 * i + 3 + c];
          }
          map.visibility(kPoints, xyz.data(), xyz.data() + 1, xyz.data() + 2, nrm.data(), nrm.data() + 1, nrm.data() + 2,
                         3, out.data());
        }
        return out;
      };
      const std::vector<float> scalar = run(nullptr, true);
      EXPECT_EQ(run(nullptr, false), scalar);
      int partial = 0, shadowed = 0;
      for (float v : scalar) {
        partial += v > 0.0f && v < 1.0f;
        shadowed += v == 0.0f;
      }
      EXPECT_GT(shadowed, 10);
      if (filter != ShadowFilter::none) {
        EXPECT_GT(partial, 10);
      }
      for (const Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
        const raster::simd::Kernels* k = raster::simd_raster_kernels(isa);
        if (!k) continue;
        for (const bool soa : {true, false}) {
          const std::vector<float> simd = run(k->shadow_map, soa);
          ASSERT_EQ(simd.size(), scalar.size());
          EXPECT_EQ(std::memcmp(simd.data(), scalar.data(), simd.size() * sizeof(float)), 0)
              << to_string(isa) << " " << to_string(filter) << " kind " << map.kind();
          ++compared;
        }
      }
    }
  }
  EXPECT_GE(compared, 12 * 2);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// A renderer keeps its shadow maps from frame to frame (a tile no caster reaches is cleared once)
// and its ray-cast hierarchy while the casters do not change: frames after a moved caster, a
// moved camera, a new resolution or a new tile size are the bytes a fresh renderer draws.
TEST(ShadowMaps, AReusedRendererDrawsWhatAFreshOneDraws) {
  auto draw = [](Renderer& r, const Scene& s, int tile_size) {
    Canvas c(kSize, kSize);
    RenderOptions o = test::gl_options();
    o.shading = ShadingMode::phong;
    o.tile_size = tile_size;
    EXPECT_TRUE(r.render(s, o, c.view()).ok());
    return c.pixels();
  };
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::raycast, ShadowMethod::volume}) {
    for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
      Scene a = with_map(base, ShadowFilter::pcf3x3, 512);
      a.lights[0].shadow.method = method;
      Scene moved = a;
      moved.objects[1].model.block<3, 1>(0, 3) = Vec3(1.0f, 1.2f, -1.0f);
      Scene finer = moved;
      finer.lights[0].shadow.resolution = 1024;
      Scene turned = finer;  // the camera moves, the casters stay
      turned.camera.eye = Vec3(1.0f, 11.0f, 3.0f);
      Scene fewer = turned;  // a caster stops casting
      fewer.objects[1].cast_shadows = false;
      Scene reshaped = moved;  // a caster's mesh changes (its adjacency and hierarchy with it)
      for (Vec3& p : reshaped.meshes[1].mesh.positions) p = Vec3(p.x() * 1.5f, p.y() * 0.5f, p.z());
      Renderer reused;
      draw(reused, a, 64);
      for (const auto& [scene, tile] : {std::pair<const Scene*, int>{&moved, 64}, {&finer, 64}, {&turned, 64}, {&a, 32},
                                        {&moved, 128}, {&fewer, 64}, {&reshaped, 64}, {&a, 64}}) {
        Renderer fresh;
        EXPECT_EQ(draw(reused, *scene, tile), draw(fresh, *scene, tile)) << "tile " << tile << " " << to_string(method);
      }
    }
  }
}

}  // namespace
}  // namespace facet

#include "shadow/volume.hpp"

namespace facet {
namespace {

// Stencil shadow volumes (z-fail): exact hard shadows per pixel, against the sphere's analytic shadow and against ray-
// cast shadows away from their edges; determinism; the adjacency.
TEST(ShadowVolumes, MatchTheSpheresExactShadow) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    SCOPED_TRACE(static_cast<int>(base.lights[0].type));
    const auto [in_shadow, in_light] = compare_with_exact_shadow(with_volume(base), 8.0 / kSize * 2.0);
    EXPECT_GT(in_shadow, 100);
    EXPECT_GT(in_light, 500);
  }
}

TEST(ShadowVolumes, SameBytesForEveryThreadCountAndPath) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    expect_same_for_threads_and_paths(with_volume(base));
  }
}

TEST(ShadowVolumes, NothingToCastIsTheUnshadowedImage) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    expect_unshadowed_without_casters_or_receivers(with_volume(base));
  }
}

TEST(ShadowVolumes, AgreeWithRaycastBeyondAPixelOfAnEdge) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    const Agreement a = compare_with_raycast(base, 1, ShadowFilter::none, ShadowMethod::volume);
    EXPECT_GT(a.shadowed, 100);
    EXPECT_GT(a.compared, kSize * kSize / 2);
  }
}

// Two volume-shadowed lights in one frame (a sun and a lamp): each its own mask.
TEST(ShadowVolumes, SeveralLights) {
  Scene s = sphere_over_plane();
  Light lamp = point_over_sphere().lights[0];
  lamp.diffuse = Color3(0.4f, 0.3f, 0.2f);
  s.lights[0].diffuse = Color3(0.4f, 0.5f, 0.6f);
  s.lights.push_back(lamp);
  const Agreement a = compare_with_raycast(s, 1, ShadowFilter::none, ShadowMethod::volume);
  EXPECT_GT(a.shadowed, 150);
}

// The camera inside a shadow volume, its near plane cutting the volume: what z-fail is for (z-pass counting would
// invert the shadow here).
TEST(ShadowVolumes, CameraInsideTheShadow) {
  for (const Scene& base : {sphere_over_plane(), point_over_sphere()}) {
    Scene s = base;
    // On the line from the sphere's centre away from the light, between the sphere and the plane.
    const Vec3 away = base.lights[0].type == LightType::directional
                          ? base.lights[0].direction
                          : Vec3((kCentre - base.lights[0].position).normalized());
    s.camera.eye = kCentre + away * 1.3f;
    s.camera.target = s.camera.eye + Vec3(1.5f, -1.0f, 0.8f);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.vertical_fov_deg = 70.0f;
    s.camera.near = 0.05f;
    SCOPED_TRACE(static_cast<int>(base.lights[0].type));
    const Agreement a = compare_with_raycast(s, 1, ShadowFilter::none, ShadowMethod::volume);
    EXPECT_GT(a.shadowed, 100);
  }
}

// An open mesh (a square, one-sided) casts from both sides, as with ray-cast shadows: facing the light or turned away
// from it, the same shadow.
TEST(ShadowVolumes, OpenMeshesCastFromBothSides) {
  for (const float turn : {0.0f, 3.14159265f}) {
    Scene s = sphere_over_plane();
    s.meshes[1] = {"square", make_plane(1.6f, 1.6f, 2)};
    s.objects[1].model =
        (Eigen::Translation3f(0.0f, 1.5f, 0.0f) * Eigen::AngleAxisf(turn + 0.3f, Vec3::UnitX())).matrix();
    const Agreement a = compare_with_raycast(s, 1, ShadowFilter::none, ShadowMethod::volume);
    EXPECT_GT(a.shadowed, 150) << turn;
  }
}

// Adjacency: shapes with split vertices (seams, creases) are closed once welded; a plane is open; a triangle turned the
// wrong way opens a mesh.
TEST(ShadowVolumes, AdjacencyWeldsSplitVertices) {
  shadow::MeshEdges e;
  for (const Mesh& closed : {make_uv_sphere(1.0f, 24, 12), make_cube(1.0f, 1), make_cube(2.0f, 3)}) {
    e.build(closed);
    EXPECT_TRUE(e.closed);
    EXPECT_TRUE(e.built_from(closed));
    std::size_t uses = 0;
    for (std::size_t k = 0; k + 1 < e.first.size(); ++k) uses += e.first[k + 1] - e.first[k];
    EXPECT_EQ(uses,
              3 * closed.triangle_count());  // no degenerate triangle in these shapes
  }
  const Mesh plane = make_plane(1.0f, 1.0f, 3);
  e.build(plane);
  EXPECT_FALSE(e.closed);
  Mesh flipped = make_cube(1.0f, 1);
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_FALSE(e.built_from(flipped));
  e.build(flipped);
  EXPECT_FALSE(e.closed);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// Flat and Gouraud shading with shadows (the renderer's sub-frames summed per pixel): the shadow's
// edge runs through triangles, per pixel, with every method.
struct Images {
  std::vector<std::uint8_t> shadowed, lit, dark;
};
Images flat_or_gouraud(const Scene& s, ShadingMode shading, int threads = 0) {
  Scene lit = s, dark = s;
  lit.lights[0].shadow.method = ShadowMethod::none;
  dark.lights[0].enabled = false;
  return {render(s, threads, LightingPath::simd, Isa::best, nullptr, shading),
          render(lit, threads, LightingPath::simd, Isa::best, nullptr, shading),
          render(dark, threads, LightingPath::simd, Isa::best, nullptr, shading)};
}
bool within_one_step(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, std::size_t at) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(int(a[at + static_cast<std::size_t>(c)]) - int(b[at + static_cast<std::size_t>(c)])) > 1) return false;
  }
  return true;
}

TEST(ShadowsInFlatAndGouraud, MatchTheSpheresExactShadowPerPixel) {
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    for (const ShadowMethod method : {ShadowMethod::raycast, ShadowMethod::map, ShadowMethod::volume}) {
      for (const Scene& base : {sphere_over_plane(), spot_over_sphere()}) {
        Scene s = base;
        s.lights[0].shadow.method = method;
        s.lights[0].shadow.filter = ShadowFilter::none;
        SCOPED_TRACE(std::string(to_string(shading)) + " " + to_string(method) + " light " +
                     std::to_string(static_cast<int>(s.lights[0].type)));
        const Images img = flat_or_gouraud(s, shading);
        const double margin = 8.0 / kSize * 2.0 + (method == ShadowMethod::map ? map_margin(s.lights[0]) : 0.0);
        int in_shadow = 0, in_light = 0, wrong = 0;
        for (int y = 0; y < kSize; ++y) {
          for (int x = 0; x < kSize; ++x) {
            const PlanePoint pp = plane_point(s, x, y);
            if (pp.behind_sphere || std::abs(pp.p.x()) > 3.9f || std::abs(pp.p.z()) > 3.9f) continue;
            const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
            if (within_one_step(img.lit, img.dark, at)) continue;  // the light does not reach it
            if (pp.shadow_margin < -margin) {
              ++in_shadow;
              if (!within_one_step(img.shadowed, img.dark, at) && ++wrong <= 5) ADD_FAILURE() << "lit in the shadow at " << x << ", " << y;
            } else if (pp.shadow_margin > margin) {
              ++in_light;
              if (!within_one_step(img.shadowed, img.lit, at) && ++wrong <= 5) ADD_FAILURE() << "shadowed in the light at " << x << ", " << y;
            }
          }
        }
        EXPECT_EQ(wrong, 0);
        EXPECT_GT(in_shadow, 100);
        EXPECT_GT(in_light, 500);
      }
    }
  }
}

// Per pixel, not per vertex: the plane has 4 x 4 quads, so a triangle of it holds both shadowed
// and lit pixels, which per-vertex visibility could not draw.
TEST(ShadowsInFlatAndGouraud, ATriangleHoldsBothShadowAndLight) {
  Scene s = sphere_over_plane();
  const Images img = flat_or_gouraud(s, ShadingMode::flat);
  // Flat: one colour per triangle without shadows; with them, a triangle's pixels take two values.
  // The plane's triangle under the shadow's edge at world (1.5, 0, 0): find pixels of both kinds
  // within one of its quads (x in [0, 2], z in [0, 2]).
  int shadowed = 0, lit = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const PlanePoint pp = plane_point(s, x, y);
      if (pp.behind_sphere || pp.p.x() < 0.05f || pp.p.x() > 1.95f || pp.p.z() < 0.05f || pp.p.z() > 1.95f) continue;
      const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
      shadowed += std::memcmp(&img.shadowed[at], &img.lit[at], 3) != 0 ? 1 : 0;
      lit += within_one_step(img.shadowed, img.lit, at) ? 1 : 0;
    }
  }
  EXPECT_GT(shadowed, 20);
  EXPECT_GT(lit, 20);
}

TEST(ShadowsInFlatAndGouraud, SameBytesForEveryThreadCount) {
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    for (const ShadowMethod method : {ShadowMethod::raycast, ShadowMethod::map, ShadowMethod::volume}) {
      Scene s = point_over_sphere();
      s.lights[0].shadow.method = method;
      const auto one = render(s, 1, LightingPath::simd, Isa::best, nullptr, shading);
      EXPECT_EQ(render(s, 2, LightingPath::simd, Isa::best, nullptr, shading), one) << to_string(method);
      EXPECT_EQ(render(s, 8, LightingPath::simd, Isa::best, nullptr, shading), one) << to_string(method);
    }
  }
}

// Nothing casting: every pixel sees the light, and the summed sub-frames are the unshadowed frame
// to within a step (the shadowed light's terms are interpolated apart from the rest).
TEST(ShadowsInFlatAndGouraud, NothingToCastIsTheUnshadowedImageWithinAStep) {
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    Scene s = spot_over_sphere();
    for (Instance& i : s.objects) i.cast_shadows = false;
    Scene none = s;
    none.lights[0].shadow.method = ShadowMethod::none;
    const auto a = render(s, 0, LightingPath::simd, Isa::best, nullptr, shading);
    const auto b = render(none, 0, LightingPath::simd, Isa::best, nullptr, shading);
    for (std::size_t at = 0; at < a.size(); at += 4) ASSERT_TRUE(within_one_step(a, b, at)) << at / 4;
  }
}

// The same with textures and emission added after them (Material::emissive_texture): the
// emission belongs to the base sub-frame alone (counted twice, or modulated, it would show).
TEST(ShadowsInFlatAndGouraud, EmissionAfterTheTextureIsCountedOnce) {
  auto checker = [](int n, std::uint8_t lo, std::uint8_t hi) {
    std::vector<std::uint8_t> rgba;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::uint8_t v = (i + j) % 2 ? hi : lo;
        rgba.insert(rgba.end(), {v, static_cast<std::uint8_t>(v / 2), static_cast<std::uint8_t>(255 - v), 255});
      }
    Result<Texture> t = make_texture("checker", n, n, rgba, TextureOptions{});
    EXPECT_TRUE(t.ok());
    return std::move(*t);
  };
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    Scene s = spot_over_sphere();
    s.textures.push_back(checker(8, 40, 220));
    s.textures.push_back(checker(4, 0, 255));
    Material& m = s.materials[0];
    m.diffuse_texture = 0;
    m.emissive_texture = 1;
    m.emissive = Color3(0.3f, 0.2f, 0.1f);
    for (Instance& i : s.objects) i.cast_shadows = false;
    Scene none = s;
    none.lights[0].shadow.method = ShadowMethod::none;
    const auto a = render(s, 0, LightingPath::simd, Isa::best, nullptr, shading);
    const auto b = render(none, 0, LightingPath::simd, Isa::best, nullptr, shading);
    for (std::size_t at = 0; at < a.size(); at += 4) ASSERT_TRUE(within_one_step(a, b, at)) << to_string(shading) << " " << at / 4;
  }
}

}  // namespace
}  // namespace facet
