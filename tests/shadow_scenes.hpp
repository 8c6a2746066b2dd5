// The shadow tests' scenes and comparisons (shadow_test.cpp, shadow_volume_test.cpp): a sphere over
// a plane, the sphere's exact shadow on it, renders of it, and agreement with ray-cast shadows.
#pragma once

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "render_support.hpp"

// In the tests' own unnamed namespace, as when they were one file; inline, so that a file
// leaving one unused is not warned.
namespace facet {
namespace {

using test::Canvas;

constexpr int kSize = 96;
inline const Vec3 kCentre(0.0f, 1.5f, 0.0f);
constexpr float kRadius = 1.0f;

// A plane seen from above, a sphere over it, one directional light at 45 degrees that casts
// ray-cast shadows; Phong, no specular.
inline Scene sphere_over_plane() {
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

inline std::vector<std::uint8_t> render(const Scene& s, int threads = 0, LightingPath path = LightingPath::simd,
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
inline PlanePoint plane_point(const Scene& s, int x, int y) {
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
inline std::pair<int, int> compare_with_exact_shadow(const Scene& s, double margin, bool hard = true) {
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

// The same bytes for 1, 2, 3 and 8 threads; the lighting paths differ in the last bit of their
// arithmetic (within a step), not in what is shadowed.
inline void expect_same_for_threads_and_paths(const Scene& s) {
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
inline void expect_unshadowed_without_casters_or_receivers(const Scene& s) {
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

inline Scene with_map(Scene s, ShadowFilter filter = ShadowFilter::pcf3x3, int resolution = 2048) {
  for (Light& l : s.lights) {
    l.shadow.method = ShadowMethod::map;
    l.shadow.filter = filter;
    l.shadow.resolution = resolution;
  }
  return s;
}

inline Scene with_volume(Scene s) {
  for (Light& l : s.lights) l.shadow.method = ShadowMethod::volume;
  return s;
}

inline Scene spot_over_sphere() {
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

inline Scene point_over_sphere() {
  Scene s = sphere_over_plane();
  Light& lamp = s.lights[0];
  lamp.type = LightType::point;
  lamp.position = Vec3(-2.5f, 4.0f, 0.3f);
  return s;
}

// The world size of one of the map's texels on the plane near the shadow, a generous bound for
// these scenes (the directional map spans at most the plane's 8 x 8 units; the spot and cube faces
// are at most 7 units from the shadow, with a field of view of at most 2 x 45 degrees, widened).
inline double texel_bound(const Light& l) {
  const double r = l.shadow.resolution;
  return l.type == LightType::directional ? 11.4 / r : 2.0 * 7.0 * 1.1 / r;
}

// How far the map's shadow edge may lie from the exact one on the plane: a pixel's footprint, and
// the filter's reach and the bias (normal, and the slope term at 45 degrees), in texels, stretched
// by the light's slant on the plane (at most 2x here).
inline double map_margin(const Light& l) {
  const double radius = shadow_filter_width(l.shadow.filter) / 2.0 + 0.5;
  const double reach = radius * (1.0 + l.shadow.bias.normal + l.shadow.bias.slope + l.shadow.bias.constant);
  return 8.0 / kSize * 1.2 + 2.0 * reach * texel_bound(l);
}

// Renders `s` with shadow maps and with ray-cast shadows (the exact reference) and compares them:
// every pixel farther than `band` pixels from a ray-cast shadow edge (a pixel whose ray-cast
// visibility differs from a neighbour's) has the ray-cast image's bytes. Returns the pixels in
// ray-cast shadow and how many pixels were compared.
struct Agreement {
  int shadowed = 0, compared = 0, wrong = 0;
};
inline Agreement compare_with_raycast(const Scene& s, int band, ShadowFilter filter = ShadowFilter::pcf3x3,
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

}  // namespace
}  // namespace facet
