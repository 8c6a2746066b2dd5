// `facet accuracy`, parts 5 and 6: the shadow methods against ray-cast shadows, and environment
// maps per vertex and per pixel against exact reflection rays.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <vector>

#include "accuracy.hpp"
#include "cli.hpp"
#include "common/format.hpp"
#include "common/look_at.hpp"
#include "lighting/point_shader.hpp"
#include "tile/tile_raster.hpp"
#include "texture/sampler.hpp"

namespace facet::cli {
namespace {

// 5. Shadows against ray-cast shadows (see the header).
Scene shadow_scene(LightType type) {
  Scene s;
  s.meshes.push_back({"ground", make_plane(16.0f, 16.0f, 8)});
  s.meshes.push_back({"ball", make_uv_sphere(1.0f, 96, 48)});
  s.meshes.push_back({"box", make_cube(1.0f, 1)});
  Material ground, red, blue;
  ground.ambient = ground.diffuse = Color3(0.8f, 0.8f, 0.8f);
  red.ambient = red.diffuse = Color3(0.8f, 0.15f, 0.1f);
  blue.ambient = blue.diffuse = Color3(0.2f, 0.3f, 0.8f);
  for (Material* m : {&ground, &red, &blue}) m->specular = Color3(0.3f, 0.3f, 0.3f), m->shininess = 24.0f;
  s.materials = {ground, red, blue};
  s.objects.push_back(Instance{0, 0});
  Instance ball{1, 1}, box{2, 2};
  ball.model.block<3, 1>(0, 3) = Vec3(-0.8f, 1.3f, 0.0f);
  box.model = (Eigen::Translation3f(1.6f, 0.5f, 0.6f) * Eigen::AngleAxisf(0.5236f, Vec3::UnitY())).matrix();
  s.objects.push_back(ball);
  s.objects.push_back(box);
  Light l;
  l.type = type;
  l.diffuse = Color3(0.8f, 0.8f, 0.8f);
  l.specular = Color3(0.5f, 0.5f, 0.5f);
  if (type == LightType::directional) {
    l.direction = Vec3(-0.5f, -1.0f, -0.3f).normalized();
  } else if (type == LightType::spot) {
    l.position = Vec3(2.5f, 5.0f, 2.5f);
    l.direction = Vec3(-0.45f, -1.0f, -0.45f).normalized();
    l.spot_shape = SpotShape::smooth_cone;
    l.spot_inner_deg = 30.0f;
    l.spot_outer_deg = 40.0f;
  } else {
    l.position = Vec3(-2.6f, 2.2f, 1.6f);
  }
  s.lights.push_back(l);
  s.global_ambient = Color3(0.1f, 0.1f, 0.12f);
  s.camera.eye = Vec3(0.0f, 3.5f, 8.0f);
  s.camera.target = Vec3(0.0f, 0.6f, 0.0f);
  s.camera.vertical_fov_deg = 45.0f;
  s.camera.near = 0.1f;
  s.camera.far = 60.0f;
  return s;
}

// The map contract: every pixel that differs from the ray-cast image lies within this many
// pixels (of a 640-pixel-wide image) of a ray-cast shadow edge or an object's outline. A map's
// shadow edge moves by the filter's reach and the bias, a few texels, which light at grazing
// angles stretches over several pixels; and at 1024^2 and finer at most 1.5 % of the receivers
// differ.
double map_edge_contract(int resolution, int taps) { return 8.0 + (taps + 1) * 2048.0 / resolution; }

// The volume contract: differing pixels lie within this many pixels of a ray-cast shadow edge
// or an outline, at any image size (a shadow edge's own pixels may round either way in either
// method), and at most this share of the receivers differ.
constexpr double kVolumeEdgeContract = 1.0;
constexpr double kVolumeShareContract = 0.002;

}  // namespace

Status shadow_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 320 : 640, h = quick ? 180 : 360;
  struct Kind {
    LightType type;
    const char* name;
  };
  for (const Kind kind : {Kind{LightType::directional, "directional"}, Kind{LightType::spot, "spot"},
                          Kind{LightType::point, "point"}}) {
    const Scene base = shadow_scene(kind.type);
    auto render = [&](const Scene& s, double* ms) -> Result<std::vector<std::uint8_t>> {
      std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
      RenderOptions o;
      o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
      o.shading = ShadingMode::phong;
      o.threads = 1;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      Renderer r(o);
      if (Status st = r.render(s, view); !st.ok()) return st;
      if (ms) {  // the same frame again, one thread: its time with this method
        const int repeats = quick ? 2 : 6;
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < repeats; ++i) (void)r.render(s, view);
        *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      }
      return rgba;
    };
    auto with = [&](ShadowMethod method, int resolution, ShadowFilter filter) {
      Scene s = base;
      s.lights[0].shadow.method = method;
      s.lights[0].shadow.resolution = resolution;
      s.lights[0].shadow.filter = filter;
      return s;
    };
    Scene off = base;
    off.lights[0].enabled = false;
    double ray_ms = 0;
    const auto exact = render(with(ShadowMethod::raycast, 2048, ShadowFilter::none), &ray_ms);
    const auto lit = render(base, nullptr), dark = render(off, nullptr);
    if (!exact) return exact.status();
    if (!lit) return lit.status();
    if (!dark) return dark.status();
    const std::size_t n = static_cast<std::size_t>(w * h);
    auto differ = [](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, std::size_t i, int tol) {
      for (int c = 0; c < 3; ++c) {
        if (std::abs(int(a[4 * i + c]) - int(b[4 * i + c])) > tol) return true;
      }
      return false;
    };
    // Which object each pixel shows: the scene unlit, each object glowing in its own colour.
    Scene ids = base;
    ids.lights[0].enabled = false;
    ids.global_ambient = Color3(0, 0, 0);
    for (std::size_t m = 0; m < ids.materials.size(); ++m) {
      ids.materials[m].ambient = Color3(0, 0, 0);
      ids.materials[m].emissive = Color3(m == 0 ? 1.0f : 0.0f, m == 1 ? 1.0f : 0.0f, m == 2 ? 1.0f : 0.0f);
    }
    const auto object = render(ids, nullptr);
    if (!object) return object.status();
    std::vector<std::uint8_t> receiver(n), shadowed(n);
    for (std::size_t i = 0; i < n; ++i) {
      receiver[i] = differ(*lit, *dark, i, 0);
      shadowed[i] = differ(*exact, *lit, i, 0);
    }
    // Distance (in pixels, the larger of |dx| and |dy|) to the nearest edge: a ray-cast shadow
    // edge (a pixel whose shadowed state differs from a neighbour's) or an object's outline (a
    // pixel whose object differs from a neighbour's: where a caster stands on a receiver, a
    // filtered map's shadow reaches past the caster's lit foot by the filter's width).
    std::vector<int> edge_distance(n, 1 << 20);
    std::vector<std::size_t> frontier;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y * w + x);
        auto apart = [&](std::size_t j) { return shadowed[j] != shadowed[i] || std::memcmp(&(*object)[4 * j], &(*object)[4 * i], 3) != 0; };
        const bool edge = (x + 1 < w && apart(i + 1)) || (y + 1 < h && apart(i + w)) || (x > 0 && apart(i - 1)) ||
                          (y > 0 && apart(i - w));
        if (edge) edge_distance[i] = 0, frontier.push_back(i);
      }
    }
    for (int d = 1; !frontier.empty(); ++d) {  // breadth first over the 8 neighbours
      std::vector<std::size_t> next;
      for (const std::size_t i : frontier) {
        const int x = static_cast<int>(i % static_cast<std::size_t>(w)), y = static_cast<int>(i / static_cast<std::size_t>(w));
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int u = x + dx, v = y + dy;
            if (u < 0 || v < 0 || u >= w || v >= h) continue;
            const std::size_t j = static_cast<std::size_t>(v * w + u);
            if (edge_distance[j] > d) edge_distance[j] = d, next.push_back(j);
          }
        }
      }
      frontier.swap(next);
    }
    auto measure = [&](const std::string& method, const std::string& item, const Scene& s, double edge_contract,
                       double share_contract) -> Status {
      Row r;
      r.kind = "shadow";
      r.method = method;
      r.item = std::string(kind.name) + (item.empty() ? "" : " " + item);
      const auto got = render(s, &r.ms_per_frame);
      if (!got) return got.status();
      std::size_t receivers = 0, differing = 0;
      double sq = 0;
      for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
          const double e = double((*got)[4 * i + c]) - double((*exact)[4 * i + c]);
          sq += e * e;
          r.max_step = std::max(r.max_step, static_cast<int>(std::abs(e)));
        }
        if (!receiver[i]) continue;
        ++receivers;
        if (!differ(*got, *exact, i, 1)) continue;
        ++differing;
        r.edge_px = std::max(r.edge_px, double(edge_distance[i]));
      }
      const double mse = sq / double(3 * n);
      r.psnr_db = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : INFINITY;
      r.share = receivers ? double(differing) / double(receivers) : 0.0;
      r.verdict = "ok";
      if (r.edge_px > edge_contract) {
        r.verdict = "differs " + number(r.edge_px) + " px from an edge (contract " + number(edge_contract) + ")";
      } else if (r.share > share_contract) {
        r.verdict = "too many pixels differ (contract " + number(100 * share_contract) + " %)";
      }
      rows.push_back(r);
      return {};
    };
    // Ray-cast against itself: the check that the comparison itself finds nothing.
    if (Status st = measure("raycast", "", with(ShadowMethod::raycast, 2048, ShadowFilter::none), 0.0, 0.0); !st.ok()) {
      return st;
    }
    // Volumes: exact per pixel, so only pixels next to a shadow edge or an outline may differ
    // (where the pixel's Phong position and the mask's pixel round apart, or the two methods'
    // rounding decides a grazing pixel differently), and few of them.
    if (Status st = measure("volume", "", with(ShadowMethod::volume, 2048, ShadowFilter::none), kVolumeEdgeContract,
                            kVolumeShareContract);
        !st.ok()) {
      return st;
    }
    const std::vector<int> resolutions = quick ? std::vector<int>{512, 2048} : std::vector<int>{256, 512, 1024, 2048, 4096};
    const std::vector<ShadowFilter> filters =
        quick ? std::vector<ShadowFilter>{ShadowFilter::none, ShadowFilter::pcf3x3}
              : std::vector<ShadowFilter>{ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5};
    for (const int res : resolutions) {
      for (const ShadowFilter f : filters) {
        const Status st = measure(std::string("map ") + to_string(f), std::to_string(res), with(ShadowMethod::map, res, f),
                                  map_edge_contract(res, shadow_filter_width(f)) * w / 640.0, res >= 1024 ? 0.015 : 1.0);
        if (!st.ok()) return st;
      }
    }
  }
  return {};
}

namespace {

// --- Environment maps: per vertex (Gouraud's texgen) against per pixel (Phong) -----------------

// A w x w face of a smooth sky (each channel affine in the unit direction) for face f of a cube
// map, top row first; GL's table 3.21 with t from the face's top.
Texture sky_face(int f, int size) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size * size) * 4);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double sc = 2 * (i + 0.5) / size - 1, tc = 2 * (j + 0.5) / size - 1;
      const Eigen::Vector3d d[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc}, {sc, -1, -tc}, {sc, -tc, 1}, {-sc, -tc, -1}};
      const Eigen::Vector3d u = d[f].normalized();
      std::uint8_t* p = &rgba[static_cast<std::size_t>(j * size + i) * 4];
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::lround(255.0 * (0.5 + 0.45 * u[c])));
      p[3] = 255;
    }
  }
  TextureOptions o;
  o.filter = TextureFilter::bilinear;
  o.wrap = TextureWrap::clamp;
  return std::move(*make_texture("sky", size, size, rgba, o));
}

}  // namespace

// A mirror ball (radius 1, `segments` around) cube-mapped with the sky, its colour the
// environment alone, against exact reflection rays of the true sphere into the same faces (the
// reference sampler in double), over the pixels well inside its silhouette; the frame's time on
// one thread beside it.
Status environment_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 160 : 480, h = w;
  Scene s;
  s.camera.eye = Vec3(0, 0, 3.2f);
  s.camera.near = 0.5f;
  s.camera.far = 10.0f;
  s.global_ambient = Color3(0, 0, 0);
  for (int f = 0; f < 6; ++f) s.textures.push_back(sky_face(f, 32));
  Material m;
  m.ambient = m.diffuse = Color3(0, 0, 0);
  m.environment.mode = EnvironmentMode::cube;
  m.environment.blend = EnvironmentBlend::mix;
  for (int f = 0; f < 6; ++f) m.environment.maps[f] = f;
  s.materials.push_back(m);
  s.objects.push_back({});
  texture::Sampler faces[6];
  for (int f = 0; f < 6; ++f) faces[f] = texture::make_sampler(s.textures[static_cast<std::size_t>(f)]);
  const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
  const Eigen::Vector3d eye = s.camera.eye.cast<double>();
  const double k = std::tan(0.5 * s.camera.vertical_fov_deg * std::numbers::pi / 180.0);
  auto exact = [&](const Eigen::Vector3d& hit) {  // world space; the unit sphere's normal is hit
    const Eigen::Vector3d u = (hit - eye).normalized(), n = hit.normalized();
    const Eigen::Vector3d r = u - 2.0 * n * n.dot(u);
    return texture::sample_cube_reference(faces, r.x(), r.y(), r.z());
  };
  const std::vector<int> tessellations = quick ? std::vector<int>{24, 96} : std::vector<int>{12, 24, 48, 96, 192};
  for (const int segments : tessellations) {
    s.meshes.assign(1, {"ball", make_uv_sphere(1.0f, segments, segments / 2)});
    for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
      std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
      RenderOptions o;
      o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
      o.shading = shading;
      o.threads = 1;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      Renderer r(o);
      if (Status st = r.render(s, view); !st.ok()) return st;
      Row row;
      row.kind = "environment";
      row.method = shading == ShadingMode::gouraud ? "per vertex (gouraud)" : "per pixel (phong)";
      row.item = "segments=" + std::to_string(segments);
      const int repeats = quick ? 2 : 8;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < repeats; ++i) (void)r.render(s, view);
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      double sum = 0;
      std::size_t pixels = 0, close = 0;
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          const Eigen::Vector3d dir =
              to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * k, (1 - 2.0 * (y + 0.5) / h) * k, -1).normalized();
          const double b = eye.dot(dir), disc = b * b - (eye.squaredNorm() - 1.0);
          if (disc < 0.15) continue;  // near the silhouette the tessellated outline differs from the sphere's
          const auto want = exact(eye + (-b - std::sqrt(disc)) * dir);
          bool near = true;
          for (int c = 0; c < 3; ++c) {
            const double e = std::abs(double(rgba[static_cast<std::size_t>((y * w + x) * 4 + c)]) - 255.0 * want[static_cast<std::size_t>(c)]);
            sum += e;
            row.max_lsb = std::max(row.max_lsb, e);
            near = near && e <= 2.5;
          }
          ++pixels;
          close += near;
        }
      }
      row.mean_lsb = pixels ? sum / double(3 * pixels) : 0.0;
      row.max_step = static_cast<int>(std::lround(row.max_lsb));
      row.share = pixels ? double(close) / double(pixels) : 0.0;  // within 2 steps
      // The contract (tests/environment_test.cpp checks the same): finely tessellated, both
      // within half a step on average; coarse, per pixel is the better of the two.
      row.verdict = segments >= 96 && row.mean_lsb > 0.5 ? "mean over 0.5 step at 96+ segments" : "ok";
      rows.push_back(row);
    }
  }
  return {};
}

}  // namespace facet::cli
