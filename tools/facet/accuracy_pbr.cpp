// `facet accuracy`, parts 10 and 11: PBR materials per vertex and per pixel under the neutral
// studio, as a glTF model is drawn with no option given (Khronos PBR Neutral, sRGB), against the
// reference path per pixel on a finely tessellated ball; and the prefilter's face size and sample
// count against the integral the prefiltered cube tabulates.
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include <algorithm>
#include <functional>
#include <random>

#include "accuracy.hpp"
#include "cli.hpp"
#include "common/look_at.hpp"
#include "lighting/image_light.hpp"

namespace facet::cli {

// Three balls side by side (a rough dielectric, a polished metal, a half-metal), a ball of
// `segments` around each, lit by the studio alone, per vertex (Gouraud) and per pixel (Phong) on
// the simd path, against per-pixel lighting on the reference (double) path at 512 segments, over
// the pixels well inside the silhouettes (the tessellated outline differs from the sphere's); the
// frame's time on one thread beside it, the studio's prefiltering not counted (a renderer keeps it).
Status pbr_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 240 : 720, h = w / 3;
  Scene s;
  s.camera.eye = Vec3(0.0f, 0.0f, 4.2f);
  s.camera.near = 1.0f;
  s.camera.far = 10.0f;
  s.camera.vertical_fov_deg = 30.0f;
  s.environment_light.source = EnvironmentSource::studio;
  s.display.tone_mapping = ToneMapping::neutral;
  s.global_ambient = Color3::Zero();
  const float centres[3] = {-2.2f, 0.0f, 2.2f};
  const struct {
    Color3 base;
    float metallic, roughness;
  } looks[3] = {{Color3(0.8f, 0.3f, 0.2f), 0.0f, 0.6f}, {Color3(0.95f, 0.8f, 0.5f), 1.0f, 0.2f}, {Color3(0.5f, 0.7f, 0.9f), 0.5f, 0.4f}};
  for (int k = 0; k < 3; ++k) {
    Material m;
    m.model = MaterialModel::pbr;
    m.base_color = looks[k].base, m.metallic = looks[k].metallic, m.roughness = looks[k].roughness;
    s.materials.push_back(m);
    Instance inst{0, std::uint32_t(k), Mat4::Identity()};
    inst.model(0, 3) = centres[k];
    s.objects.push_back(inst);
  }
  auto draw = [&](int segments, ShadingMode shading, LightingPath path, std::vector<std::uint8_t>& rgba,
                  std::unique_ptr<Renderer>& keep) -> Status {
    s.meshes.assign(1, {"ball", make_uv_sphere(1.0f, segments, segments / 2)});
    RenderOptions o;
    o.shading = shading;
    o.path = path;
    o.threads = 1;
    rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
    keep = std::make_unique<Renderer>(o);
    return keep->render(s, {rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false});
  };
  std::vector<std::uint8_t> reference;
  std::unique_ptr<Renderer> r;
  if (Status st = draw(512, ShadingMode::phong, LightingPath::reference, reference, r); !st.ok()) return st;
  // Pixels whose ray passes through a ball at least 0.39 of its radius inside its outline.
  const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
  const Eigen::Vector3d eye = s.camera.eye.cast<double>();
  const double t = std::tan(0.5 * s.camera.vertical_fov_deg * std::numbers::pi / 180.0), aspect = double(w) / h;
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d dir =
          to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * t * aspect, (1 - 2.0 * (y + 0.5) / h) * t, -1).normalized();
      for (const float c : centres) {
        const Eigen::Vector3d o = eye - Eigen::Vector3d(c, 0.0, 0.0);
        const double b = o.dot(dir), disc = b * b - (o.squaredNorm() - 1.0);
        if (disc >= 0.15) inside[static_cast<std::size_t>(y * w + x)] = 1;
      }
    }
  }
  const std::vector<int> tessellations = quick ? std::vector<int>{16, 128} : std::vector<int>{16, 32, 64, 128, 256};
  for (const int segments : tessellations) {
    for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
      std::vector<std::uint8_t> rgba;
      if (Status st = draw(segments, shading, LightingPath::simd, rgba, r); !st.ok()) return st;
      Row row;
      row.kind = "pbr";
      row.method = shading == ShadingMode::gouraud ? "PBR per vertex (gouraud)" : "PBR per pixel (phong)";
      row.item = "segments=" + std::to_string(segments);
      const int repeats = quick ? 2 : 8;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < repeats; ++i) (void)r->render(s, view);
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      compare_inside(rgba, reference, inside, row);
      // The contract: per pixel, the SIMD kernel and the reference agree within half a step on
      // average from 64 segments (the normals are interpolated; only the facets' positions
      // differ); per vertex the polished metal's highlights and reflections need many more
      // vertices: within a step at 256 segments.
      if (segments >= 64 && shading == ShadingMode::phong && row.mean_lsb > 0.5) {
        row.verdict = "per-pixel PBR mean over half a step at 64+ segments";
      } else if (segments >= 256 && shading == ShadingMode::gouraud && row.mean_lsb > 1.0) {
        row.verdict = "per-vertex PBR mean over 1 step at 256+ segments";
      } else {
        row.verdict = "ok";
      }
      rows.push_back(row);
    }
  }
  return {};
}

}  // namespace facet::cli

namespace facet::cli {

// The prefilter's choices (lighting::PrefilterSettings): the prefiltered cube against the
// GGX-weighted integral of the picture it tabulates (pbr::prefiltered with 16384 samples) at
// roughness 0.2 .. 1 in 48 random directions each, for the finest face size and the samples per
// texel; the build's time on one thread beside it. The picture: 1024 x 512, a sky graded towards
// the zenith, a soft sun (6 degrees, radiance 12) and a dark ground.
Status ibl_accuracy(bool quick, std::vector<Row>& rows) {
  using V = lighting::V3<double>;
  EnvironmentLight env;
  env.source = EnvironmentSource::image;
  env.width = quick ? 256 : 1024, env.height = env.width / 2;
  env.rgb.resize(std::size_t(env.width) * std::size_t(env.height) * 3);
  const V sun{0.45, 0.55, -0.70};
  const double sun_norm = std::sqrt(dot(sun, sun));
  for (int r = 0; r < env.height; ++r) {
    for (int c = 0; c < env.width; ++c) {
      const V d = lighting::sh9::equirect_direction(c, r, env.width, env.height);
      const double up = std::max(0.0, d.y), cos_sun = dot(d, sun) / sun_norm;
      float* t = &env.rgb[3 * (std::size_t(r) * std::size_t(env.width) + std::size_t(c))];
      const double s = cos_sun > std::cos(6.0 * std::numbers::pi / 180.0) ? 12.0 : 0.0;
      t[0] = float(d.y >= 0 ? 0.35 + 0.45 * up + s : 0.16);
      t[1] = float(d.y >= 0 ? 0.45 + 0.55 * up + 0.9 * s : 0.13);
      t[2] = float(d.y >= 0 ? 0.65 + 0.85 * up + 0.7 * s : 0.10);
    }
  }
  const auto in_turn = [](std::size_t n, const std::function<void(std::size_t)>& fn) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
  };
  // The reference: per roughness level, 48 directions and their integrals over the picture (read
  // as the prefilter reads it: bilinear at full resolution).
  lighting::ImageLight probe;
  if (Status st = probe.build(env, in_turn); !st.ok()) return st;
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  struct Probe {
    V r, want;
    double roughness;
  };
  std::vector<Probe> probes;
  for (int k = 1; k < lighting::kRadianceLevels; ++k) {
    const double roughness = double(k) / (lighting::kRadianceLevels - 1);
    for (int i = 0; i < (quick ? 8 : 48); ++i) {
      V r{g(rng), g(rng), g(rng)};
      r = (1.0 / std::sqrt(dot(r, r))) * r;
      probes.push_back({r, lighting::pbr::prefiltered([&](const V& d) { return probe.source(d); }, r, roughness, quick ? 4096 : 16384),
                        roughness});
    }
  }
  const std::vector<int> sizes = quick ? std::vector<int>{128} : std::vector<int>{32, 64, 128, 256};
  const std::vector<unsigned> counts = quick ? std::vector<unsigned>{256} : std::vector<unsigned>{64, 128, 256, 512};
  for (const int size : sizes) {
    for (const unsigned samples : counts) {
      lighting::ImageLight light({size, samples});
      const auto t0 = std::chrono::steady_clock::now();
      if (Status st = light.build(env, in_turn); !st.ok()) return st;
      Row row;
      row.kind = "ibl";
      row.method = "size=" + std::to_string(size);
      row.item = "samples=" + std::to_string(samples);
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      double sum = 0.0;
      for (const Probe& p : probes) {
        const V got = light.specular(p.r, p.roughness);
        const double e = std::max({std::abs(got.x - p.want.x), std::abs(got.y - p.want.y), std::abs(got.z - p.want.z)}) /
                         std::max({p.want.x, p.want.y, p.want.z});
        sum += e;
        row.max_lsb = std::max(row.max_lsb, 100.0 * e);
      }
      row.mean_lsb = 100.0 * sum / double(probes.size());
      row.max_step = static_cast<int>(std::lround(row.max_lsb));
      // The contract: the renderer's choice (128 texels, 256 samples) within 3 % of the integral
      // on average and 10 % at worst in every direction of this sky with its sun.
      const bool chosen = size == lighting::kRadianceSize && samples == lighting::PrefilterSettings{}.samples;
      row.verdict = chosen && (row.mean_lsb > 3.0 || row.max_lsb > 10.0) ? "the renderer's prefilter over 3 % mean or 10 % worst" : "ok";
      rows.push_back(row);
    }
  }
  return {};
}

}  // namespace facet::cli
