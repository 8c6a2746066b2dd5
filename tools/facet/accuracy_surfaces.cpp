// `facet accuracy`, parts 7 to 9: bump maps per vertex and per pixel, multisampled edges against
// a 64-sample reference, and radiosity's convergence in the white furnace.
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

void compare_inside(const std::vector<std::uint8_t>& rgba, const std::vector<std::uint8_t>& reference,
                    const std::vector<std::uint8_t>& inside, Row& row) {
  double sum = 0;
  std::size_t pixels = 0, close = 0;
  for (std::size_t i = 0; i < inside.size(); ++i) {
    if (!inside[i]) continue;
    bool near = true;
    for (std::size_t c = 0; c < 3; ++c) {
      const double e = std::abs(double(rgba[4 * i + c]) - double(reference[4 * i + c]));
      sum += e;
      row.max_lsb = std::max(row.max_lsb, e);
      near = near && e <= 2;
    }
    ++pixels;
    close += near;
  }
  row.mean_lsb = pixels ? sum / double(3 * pixels) : 0.0;
  row.max_step = static_cast<int>(std::lround(row.max_lsb));
  row.share = pixels ? double(close) / double(pixels) : 0.0;
}
// Bump mapping per vertex (Gouraud with RenderOptions::vertex_relief) and per pixel (Phong) on a
// sphere of `segments` around, against per-pixel bump on the reference lighting path at 512
// segments, over the pixels well inside the silhouette; the frame's time on one thread beside it.
// The height map: smooth bumps h = (1 + sin 2 pi x / 16 sin 2 pi y / 16) / 2 on 64 x 64 texels,
// trilinear, four times around the sphere.
Status relief_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 160 : 480, h = w;
  std::vector<std::uint8_t> height(64 * 64 * 4);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const double v = 0.5 + 0.5 * std::sin(2 * std::numbers::pi * (x + 0.5) / 16) * std::sin(2 * std::numbers::pi * (y + 0.5) / 16);
      std::uint8_t* p = height.data() + 4 * (64 * y + x);
      p[0] = p[1] = p[2] = static_cast<std::uint8_t>(std::lround(255 * v)), p[3] = 255;
    }
  TextureOptions to;
  to.encoding = TextureEncoding::linear;
  Result<Texture> bumps = make_texture("bumps", 64, 64, height, to);
  if (!bumps) return bumps.status();
  Scene s;
  s.textures.push_back(std::move(*bumps));
  s.camera.eye = Vec3(0, 0.6f, 3.2f);
  s.camera.near = 0.5f;
  s.camera.far = 10.0f;
  Material m;
  m.diffuse = Color3(0.8f, 0.55f, 0.35f);
  m.ambient = Color3(0.1f, 0.1f, 0.1f);
  m.specular = Color3(0.4f, 0.4f, 0.4f);
  m.shininess = 24;
  m.bump_texture = 0;
  m.bump_scale = 6;
  m.uv_scale = Vec2(4, 2);
  s.materials.push_back(m);
  s.objects.push_back({});
  Light key;
  key.direction = Vec3(-0.5f, -0.4f, -0.7f);
  s.lights.push_back(key);
  auto draw = [&](int segments, ShadingMode shading, LightingPath path, std::vector<std::uint8_t>& rgba, Renderer** keep) -> Status {
    s.meshes.assign(1, {"ball", make_uv_sphere(1.0f, segments, segments / 2)});
    if (Status st = generate_missing_tangents(s); !st.ok()) return st;
    RenderOptions o;
    o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
    o.shading = shading;
    o.path = path;
    o.vertex_relief = true;
    o.threads = 1;
    rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
    auto* r = new Renderer(o);
    const Status st = r->render(s, {rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false});
    if (keep) {
      *keep = r;
    } else {
      delete r;
    }
    return st;
  };
  std::vector<std::uint8_t> reference;
  if (Status st = draw(512, ShadingMode::phong, LightingPath::reference, reference, nullptr); !st.ok()) return st;
  // Inside the silhouette, away from it (the tessellated outline differs from the sphere's).
  const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
  const Eigen::Vector3d eye = s.camera.eye.cast<double>();
  const double k = std::tan(0.5 * s.camera.vertical_fov_deg * std::numbers::pi / 180.0);
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d dir =
          to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * k, (1 - 2.0 * (y + 0.5) / h) * k, -1).normalized();
      const double b = eye.dot(dir), disc = b * b - (eye.squaredNorm() - 1.0);
      inside[static_cast<std::size_t>(y * w + x)] = disc >= 0.15;
    }
  const std::vector<int> tessellations = quick ? std::vector<int>{16, 256} : std::vector<int>{16, 32, 64, 128, 256};
  for (const int segments : tessellations) {
    for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
      std::vector<std::uint8_t> rgba;
      Renderer* r = nullptr;
      if (Status st = draw(segments, shading, LightingPath::simd, rgba, &r); !st.ok()) {
        delete r;
        return st;
      }
      Row row;
      row.kind = "relief";
      row.method = shading == ShadingMode::gouraud ? "bump per vertex (gouraud)" : "bump per pixel (phong)";
      row.item = "segments=" + std::to_string(segments);
      const int repeats = quick ? 2 : 8;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < repeats; ++i) (void)r->render(s, view);
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      delete r;
      compare_inside(rgba, reference, inside, row);
      // The contract: from 128 segments (where the facets no longer move the pixels' texture
      // coordinates by much) per pixel is within a step of the reference on average; per vertex
      // only approaches it, within 4 steps at 256 segments.
      if (segments >= 128 && shading == ShadingMode::phong && row.mean_lsb > 1.0) {
        row.verdict = "per-pixel bump mean over 1 step at 128+ segments";
      } else if (segments >= 256 && shading == ShadingMode::gouraud && row.mean_lsb > 4.0) {
        row.verdict = "per-vertex bump mean over 4 steps at 256+ segments";
      } else {
        row.verdict = "ok";
      }
      rows.push_back(row);
    }
  }
  return {};
}

// 8. Multisampling: the built-in scene at 320 x 180 with 1, 4, 8 and 16 samples a pixel against
// a 64-sample reference (the same frame at 2560 x 1440, one sample, each 8 x 8 block averaged in
// linear float): the mean and largest error in 8-bit steps over the edge pixels (those whose 64
// reference samples do not all show the same object or all the background, from a frame of flat
// object colours), and ms per frame on one thread. The reference shades every one of its
// samples, multisampling each pixel once, so part of the error is shading, not coverage.
Status msaa_accuracy(bool quick, std::vector<Row>& rows) {
  const Scene s = make_default_scene();
  constexpr int w = 320, h = 180, kUp = 8, W = w * kUp, H = h * kUp;
  std::vector<float> big(static_cast<std::size_t>(W) * H * 4);
  std::vector<std::uint8_t> ids(static_cast<std::size_t>(W) * H * 4);
  {
    RenderOptions o;
    o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
    if (Status st = Renderer(o).render(s, {big.data(), W, H, static_cast<std::size_t>(W) * 16, PixelFormat::rgba32f, false}); !st.ok()) {
      return st;
    }
    Scene flat = s;  // each object in its own flat colour: which object each sample shows
    flat.lights.clear();
    flat.fog.mode = FogMode::none;
    flat.global_ambient = Color3::Zero();
    flat.materials.clear();
    for (std::size_t k = 0; k < flat.objects.size(); ++k) {
      Material m;
      m.ambient = m.diffuse = m.specular = Color3::Zero();
      m.emissive = Color3(float(k + 1) / 255.0f, 0.0f, 0.0f);
      flat.materials.push_back(m);
      flat.objects[k].material = static_cast<std::uint32_t>(k);
      flat.objects[k].mesh_materials = false;
    }
    o.clear_color = {0.0f, 0.0f, 0.0f, 1.0f};
    if (Status st = Renderer(o).render(flat, {ids.data(), W, H, static_cast<std::size_t>(W) * 4, PixelFormat::rgba8, false}); !st.ok()) {
      return st;
    }
  }
  std::vector<double> reference(static_cast<std::size_t>(w * h * 3));
  std::vector<std::uint8_t> edge(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double sum[3] = {};
      const std::size_t first = (static_cast<std::size_t>(y * kUp) * W + static_cast<std::size_t>(x * kUp)) * 4;
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      for (int j = 0; j < kUp; ++j) {
        for (int k = 0; k < kUp; ++k) {
          const std::size_t at = (static_cast<std::size_t>(y * kUp + j) * W + static_cast<std::size_t>(x * kUp + k)) * 4;
          for (int c = 0; c < 3; ++c) sum[c] += std::clamp(double(big[at + static_cast<std::size_t>(c)]), 0.0, 1.0);
          edge[i] |= ids[at] != ids[first];
        }
      }
      for (int c = 0; c < 3; ++c) reference[3 * i + static_cast<std::size_t>(c)] = 255.0 * sum[c] / (kUp * kUp);
    }
  }
  for (const int samples : {1, 4, 8, 16}) {
    RenderOptions o;
    o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
    o.samples = samples;
    o.threads = 1;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
    const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
    Renderer r(o);
    if (Status st = r.render(s, view); !st.ok()) return st;
    Row row;
    row.kind = "msaa";
    row.method = std::to_string(samples) + (samples == 1 ? " sample" : " samples");
    row.item = "built-in 320x180";
    const int repeats = quick ? 3 : 20;
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < repeats; ++k) (void)r.render(s, view);
    row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
    double sum = 0;
    std::size_t pixels = 0, close = 0;
    for (std::size_t i = 0; i < edge.size(); ++i) {
      if (!edge[i]) continue;
      bool near = true;
      for (std::size_t c = 0; c < 3; ++c) {
        const double e = std::abs(double(rgba[4 * i + c]) - reference[3 * i + c]);
        sum += e;
        row.max_lsb = std::max(row.max_lsb, e);
        near = near && e <= 8;
      }
      ++pixels, close += near;
    }
    row.mean_lsb = pixels ? sum / double(3 * pixels) : 0.0;
    row.max_step = static_cast<int>(std::lround(row.max_lsb));
    row.share = pixels ? double(close) / double(pixels) : 0.0;
    rows.push_back(row);
  }
  // The contract: each count at least as close as the one below it, and 4 samples at most half
  // one sample's mean edge error.
  const std::size_t first = rows.size() - 4;
  for (std::size_t k = first; k < rows.size(); ++k) {
    Row& row = rows[k];
    row.verdict = "ok";
    if (k > first && row.mean_lsb > rows[k - 1].mean_lsb) row.verdict = "more error than fewer samples";
    if (k == first + 1 && row.mean_lsb > 0.5 * rows[first].mean_lsb) row.verdict = "4 samples not twice as close as 1";
  }
  return {};
}

// --- 9. baking: radiosity's convergence ---------------------------------------------------------
// The white furnace (a closed box of albedo 0.7 emitting 0.1 everywhere converges to
// B = 0.1 / 0.3), baked with more and more shots on 1 and 2 threads: the mean and largest error of
// each texel's radiosity in 8-bit steps, the unshot power's share (`share`) and the bake's time.
// Emission shot (not gathered, whose spikes at the box's edges would hide the convergence).
// The ambient term (on, as by default) spreads what is unshot over the box, which in a uniform
// furnace is right on average from the first shots; what stays is each texel's Monte Carlo noise
// (about 1.4 steps at 256 rays a shot). Contract: the unshot share falls as the shots grow, and
// the last bake is within 2 steps on average.
Status bake_accuracy(bool quick, std::vector<Row>& rows) {
  Scene s;
  Mesh box = make_cube(2.0f, 2);
  box.uvs.clear(), box.tangents.clear();
  for (auto& t : box.triangles) std::swap(t[1], t[2]);
  for (auto& n : box.normals) n = -n;
  s.meshes.push_back({"furnace", box});
  Material m;
  m.ambient = m.diffuse = Color3(0.7f, 0.7f, 0.7f);
  m.emissive = Color3(0.1f, 0.1f, 0.1f);
  m.specular = Color3::Zero();
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  const double expected = 0.1 / 0.3;
  for (const int threads : {1, 2}) {
    const std::size_t first = rows.size();
    for (const std::size_t shots : quick ? std::vector<std::size_t>{50, 400, 3200} : std::vector<std::size_t>{25, 50, 100, 200, 400, 800, 1600, 3200, 6400}) {
      BakeOptions o;
      o.charts.texels_per_unit = 4;
      o.gather_emitters = false;
      o.max_shots = shots;
      o.residual = 0;
      o.threads = threads;
      const auto t0 = std::chrono::steady_clock::now();
      const Result<BakeResult> r = bake_lightmaps(s, o);
      if (!r) return r.status();
      Row row;
      row.kind = "bake";
      row.method = threads == 1 ? "1 thread" : "2 threads";
      row.item = "furnace, " + std::to_string(shots) + " shots";
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const BakedLightmap& lm = r->lightmaps[0];
      double sum = 0, area = 0;
      for (std::size_t i = 0; i < lm.light.size(); ++i) {
        if (lm.area[i] == 0) continue;
        const double b = 0.1 + 0.7 * double(lm.light[i].x());
        const double e = 255.0 * std::abs(b - expected);
        sum += e * lm.area[i], area += lm.area[i];
        row.max_lsb = std::max(row.max_lsb, e);
      }
      row.mean_lsb = sum / area;
      row.max_step = static_cast<int>(std::lround(row.max_lsb));
      row.share = r->stats.entered > 0 ? r->stats.unshot / r->stats.entered : 0.0;
      rows.push_back(row);
    }
    for (std::size_t k = first; k < rows.size(); ++k) {
      Row& row = rows[k];
      row.verdict = "ok";
      if (k > first && row.share > rows[k - 1].share) row.verdict = "more power unshot after more shots";
      if (k + 1 == rows.size() && row.mean_lsb > 2.0) row.verdict = "not within 2 steps on average";
    }
  }
  return {};
}

}  // namespace facet::cli
