// Shadows (issue 17): ray-cast shadows through Embree against the analytic shadow of a sphere on
// a plane, the shadowed light's terms (ambient kept, diffuse and specular blocked), the object
// flags, determinism over threads, and the refusals (methods not implemented yet, Gouraud).
#include <cmath>
#include <cstring>

#include "shadow_scenes.hpp"

namespace facet {
namespace {

TEST(Shadows, RaycastMatchesTheSpheresExactShadow) {
  // A pixel's footprint on the plane, with room for the view's slant.
  const auto [in_shadow, in_light] = compare_with_exact_shadow(sphere_over_plane(), 8.0 / kSize * 1.2);
  EXPECT_GT(in_shadow, 200);
  EXPECT_GT(in_light, 2000);
}

// The same with a spot light above and beside the sphere: its cone covers part of the plane;
// outside the cone no ray is cast (the light gives nothing there), inside the shadow is exact.
TEST(Shadows, SpotLightMatchesTheSpheresExactShadow) {
  const Scene s = spot_over_sphere();
  // The spot light's shadow stretches more on the plane.
  const auto [in_shadow, in_light] = compare_with_exact_shadow(s, 8.0 / kSize * 2.0);
  EXPECT_GT(in_shadow, 100);
  EXPECT_GT(in_light, 500);
  // Outside the cone the image is the unshadowed one: skipping rays there changes no byte.
  Scene unshadowed = s;
  unshadowed.lights[0].shadow.method = ShadowMethod::none;
  EXPECT_EQ(std::memcmp(render(s).data(), render(unshadowed).data(), 4), 0);
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
