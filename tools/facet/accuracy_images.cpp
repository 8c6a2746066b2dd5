// `facet accuracy`, parts 3 and 4: whole images against a ray-cast reference of exact spheres,
// and the texture filters against the reference sampler.
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

// --- 3. images ---------------------------------------------------------------------------------

struct Sphere {
  Eigen::Vector3d centre;
  double radius;
  std::uint32_t material;
};

// The reference scene: three spheres on a ground plane, two lights (directional and point).
Scene image_scene(int segments, const std::vector<Sphere>& spheres, double plane_y) {
  Scene s;
  s.camera.eye = Vec3(0, 1.2f, 5.5f);
  s.camera.target = Vec3(0, 0.5f, 0);
  s.camera.vertical_fov_deg = 40;
  s.camera.near = 0.5f;
  s.camera.far = 30;
  s.global_ambient = Color3(0.1f, 0.1f, 0.1f);
  const Color3 colours[] = {{0.8f, 0.2f, 0.2f}, {0.2f, 0.7f, 0.3f}, {0.2f, 0.3f, 0.9f}, {0.6f, 0.6f, 0.55f}};
  for (int m = 0; m < 4; ++m) {
    Material mat;
    mat.ambient = colours[m] * 0.5f;
    mat.diffuse = colours[m];
    mat.specular = m < 3 ? Color3(0.6f, 0.6f, 0.6f) : Color3(0.1f, 0.1f, 0.1f);
    mat.shininess = m == 0 ? 16.0f : (m == 1 ? 60.0f : (m == 2 ? 128.0f : 8.0f));
    s.materials.push_back(mat);
  }
  s.meshes.push_back({"sphere", make_uv_sphere(1.0f, segments, std::max(2, segments / 2))});
  for (const Sphere& sp : spheres) {
    Mat4 t = Mat4::Identity();
    t.topLeftCorner<3, 3>() *= static_cast<float>(sp.radius);
    t.block<3, 1>(0, 3) = sp.centre.cast<float>();
    s.objects.push_back({0, sp.material, t});
  }
  s.meshes.push_back({"ground", make_plane(20.0f, 20.0f, std::max(1, segments / 4))});
  Mat4 g = Mat4::Identity();
  g(1, 3) = static_cast<float>(plane_y);
  s.objects.push_back({1, 3, g});
  Light sun;
  sun.direction = Vec3(-0.4f, -1.0f, -0.5f).normalized();
  sun.diffuse = Color3(0.7f, 0.7f, 0.7f);
  sun.specular = Color3(0.7f, 0.7f, 0.7f);
  s.lights.push_back(sun);
  Light lamp;
  lamp.type = LightType::point;
  lamp.position = Vec3(2.0f, 3.0f, 2.5f);
  lamp.diffuse = Color3(0.6f, 0.55f, 0.5f);
  lamp.specular = Color3(0.8f, 0.8f, 0.8f);
  lamp.linear_attenuation = 0.05f;
  s.lights.push_back(lamp);
  return s;
}

struct Image {
  int w = 0, h = 0;
  std::vector<std::uint8_t> rgba;
  std::vector<std::uint8_t> covered;
  std::vector<int> object;  // reference only: which object the pixel shows (-1: none)
};

// Ray-cast reference: per pixel centre, the nearest exact hit (spheres and the plane, in double
// precision, eye space), lit by the reference path at the exact point and normal.
Status raycast(const Scene& scene, const std::vector<Sphere>& spheres, double plane_y, int w, int h, Image& out) {
  const Eigen::Matrix4d view = look_at_d(scene.camera);
  std::vector<lighting::PointShader> shaders(scene.materials.size());
  LightingOptions o;
  o.path = LightingPath::reference;
  o.cull_lights = false;
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    if (Status s = shaders[m].prepare(scene, view, scene.materials[m], o); !s.ok()) return s;
  }
  struct Hit {
    double t = INFINITY;
    Eigen::Vector3d n;
    std::uint32_t material = 0;
    int object = -1;
  };
  std::vector<std::pair<Eigen::Vector3d, double>> centres;  // eye space
  for (const Sphere& sp : spheres) centres.emplace_back((view * sp.centre.homogeneous()).head<3>(), sp.radius);
  const Eigen::Vector3d plane_n = view.topLeftCorner<3, 3>() * Eigen::Vector3d(0, 1, 0);
  const Eigen::Vector3d plane_p = (view * Eigen::Vector4d(0, plane_y, 0, 1)).head<3>();
  const double tan_half = std::tan(double(scene.camera.vertical_fov_deg) * M_PI / 360.0);
  const double aspect = double(w) / double(h);
  const Eigen::Matrix4d eye_to_world = view.inverse();
  out.w = w, out.h = h;
  out.rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
  out.covered.assign(static_cast<std::size_t>(w * h), 0);
  out.object.assign(static_cast<std::size_t>(w * h), -1);
  lighting::SoaScratch scratch;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double ndc_x = 2.0 * (x + 0.5) / w - 1.0, ndc_y = 1.0 - 2.0 * (y + 0.5) / h;
      const Eigen::Vector3d d = Eigen::Vector3d(ndc_x * tan_half * aspect, ndc_y * tan_half, -1.0).normalized();
      Hit hit;
      for (std::size_t i = 0; i < centres.size(); ++i) {
        const Eigen::Vector3d& c = centres[i].first;
        const double r = centres[i].second;
        const double b = d.dot(c), disc = b * b - (c.squaredNorm() - r * r);
        if (disc < 0) continue;
        const double t = b - std::sqrt(disc);
        if (t > 0 && t < hit.t) hit = {t, (t * d - c) / r, spheres[i].material, static_cast<int>(i)};
      }
      const double denom = d.dot(plane_n);
      if (std::abs(denom) > 1e-12) {
        const double t = plane_p.dot(plane_n) / denom;
        const Eigen::Vector3d p = t * d;
        // The plane is a 20 x 20 square around the origin (as the mesh).
        const Eigen::Vector4d world = eye_to_world * p.homogeneous();
        if (t > 0 && t < hit.t && std::abs(world.x()) <= 10 && std::abs(world.z()) <= 10) {
          hit = {t, plane_n, 3, static_cast<int>(centres.size())};
        }
      }
      if (!std::isfinite(hit.t)) continue;
      // Beyond the far plane the rasterizer draws nothing either.
      if (hit.t * -d.z() > scene.camera.far) continue;
      const Vec3 p = (hit.t * d).cast<float>(), n = hit.n.normalized().cast<float>();
      Color3 c;
      shaders[hit.material].shade_points(1, &p, &n, &c, scratch);
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      for (int k = 0; k < 3; ++k) out.rgba[4 * i + k] = static_cast<std::uint8_t>(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
      out.rgba[4 * i + 3] = 255;
      out.covered[i] = 1;
      out.object[i] = hit.object;
    }
  }
  return {};
}

Row compare_images_inside(const Image& ref, const Image& got) {
  Row r;
  double sum = 0, sq = 0;
  long n = 0;
  // Inside a silhouette: the pixel and its 8 neighbours are covered (and, in the reference, show
  // the same object): edges, where tessellation moves the outline, are left out.
  auto interior = [&](const Image& im, int x, int y) {
    const int id = im.object.empty() ? 0 : im.object[static_cast<std::size_t>(y * im.w + x)];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= im.w || yy >= im.h) return false;
        const std::size_t j = static_cast<std::size_t>(yy * im.w + xx);
        if (!im.covered[j] || (!im.object.empty() && im.object[j] != id)) return false;
      }
    return true;
  };
  for (int y = 0; y < ref.h; ++y) {
    for (int x = 0; x < ref.w; ++x) {
      if (!interior(ref, x, y) || !interior(got, x, y)) continue;
      const std::size_t i = static_cast<std::size_t>(y * ref.w + x);
      for (int k = 0; k < 3; ++k) {
        const double d = std::abs(double(ref.rgba[4 * i + k]) - double(got.rgba[4 * i + k]));
        r.max_lsb = std::max(r.max_lsb, d);
        sum += d;
        sq += d * d;
        ++n;
      }
    }
  }
  r.mean_lsb = n ? sum / double(n) : 0;
  r.max_step = static_cast<int>(r.max_lsb);
  r.psnr_db = sq > 0 ? 10.0 * std::log10(255.0 * 255.0 / (sq / double(n))) : INFINITY;
  return r;
}

}  // namespace

Status image_accuracy(bool quick, std::vector<Row>& rows) {
  const std::vector<Sphere> spheres = {{{-1.3, 0.6, 0.0}, 0.6, 0}, {{0.1, 0.8, -0.6}, 0.8, 1}, {{1.4, 0.45, 0.5}, 0.45, 2}};
  const double plane_y = 0.0;
  const int w = quick ? 320 : 640, h = quick ? 200 : 400;
  Image ref;
  if (Status s = raycast(image_scene(8, spheres, plane_y), spheres, plane_y, w, h, ref); !s.ok()) return s;
  std::vector<int> levels = quick ? std::vector<int>{16, 64, 256} : std::vector<int>{8, 16, 32, 64, 128, 256};
  // Every image on the reference path, the scalar path and the simd path of each ISA (auto tier):
  // each against the ray-cast spheres (Phong >= 45 dB inside the silhouettes at the finest
  // tessellation), and each non-reference image against the reference path's image of the same
  // frame: the same coverage, colours within 1 step (the project's cross-path contract).
  struct PathChoice {
    std::string name;
    LightingPath path;
    Isa isa;
  };
  std::vector<PathChoice> paths = {{"reference", LightingPath::reference, Isa::best},
                                   {"scalar", LightingPath::scalar, Isa::best}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (isa_supported(isa)) paths.push_back({std::string("simd ") + to_string(isa), LightingPath::simd, isa});
  }
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (int segments : levels) {
      const Scene scene = image_scene(segments, spheres, plane_y);
      Image reference_path;
      for (const PathChoice& choice : paths) {
        Image got;
        got.w = w, got.h = h;
        got.rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
        std::vector<float> depth(static_cast<std::size_t>(w * h));
        RenderOptions o;
        o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
        o.shading = mode;
        o.path = choice.path;
        o.isa = choice.isa;
        o.clear_color = {0, 0, 0, 0};
        const ImageView view{got.rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
        const DepthView dv{depth.data(), w, h, static_cast<std::size_t>(w) * sizeof(float), false};
        Renderer r;
        if (Status s = r.render(scene, o, view, &dv); !s.ok()) return s;
        got.covered.resize(depth.size());
        for (std::size_t i = 0; i < depth.size(); ++i) got.covered[i] = depth[i] < 1.0f;
        Row row = compare_images_inside(ref, got);
        if (choice.path == LightingPath::simd && choice.isa == best_isa()) {
          // The speed side of the chart: the same frame on this path, one thread.
          RenderOptions fast = o;
          fast.threads = 1;
          Renderer timed(fast);
          (void)timed.render(scene, view);  // warm-up; the image is not used
          const int repeats = quick ? 2 : 10;
          const auto t0 = std::chrono::steady_clock::now();
          for (int i = 0; i < repeats; ++i) (void)timed.render(scene, view);
          row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
        }
        row.kind = "image";
        row.method = choice.path == LightingPath::reference ? std::string(to_string(mode))
                                                            : std::string(to_string(mode)) + " " + choice.name;
        row.item = "segments=" + std::to_string(segments);
        row.verdict = "ok";
        if (mode == ShadingMode::phong && segments == levels.back() && row.psnr_db < 45.0) row.verdict = "below 45 dB";
        if (choice.path == LightingPath::reference) {
          reference_path = got;
        } else {
          int worst = 0;
          bool same_coverage = true;
          for (std::size_t i = 0; i < got.covered.size(); ++i) {
            same_coverage &= got.covered[i] == reference_path.covered[i];
            for (int c = 0; c < 3; ++c) {
              worst = std::max(worst, std::abs(int(got.rgba[4 * i + c]) - int(reference_path.rgba[4 * i + c])));
            }
          }
          if (!same_coverage) row.verdict = "coverage differs from the reference path";
          else if (worst > 1) row.verdict = "more than 1 step from the reference path (" + std::to_string(worst) + ")";
        }
        rows.push_back(row);
      }
    }
  }
  return {};
}

// 4. Texture filters against the reference sampler (see the header).
void texture_accuracy(bool quick, std::vector<Row>& rows) {
  constexpr int kSide = 256;
  std::mt19937 rng(1234);
  std::vector<std::uint8_t> rgba(4 * kSide * kSide);
  for (std::size_t i = 0; i < rgba.size(); ++i) {  // smooth bands plus noise: every filter has work to do
    const std::size_t texel = i / 4;
    const double x = double(texel % kSide), y = double(texel / kSide);
    const double v = 127.5 + 80 * std::sin(x * 0.21 + double(i % 4)) * std::cos(y * 0.13) + double(rng() % 40) - 20;
    rgba[i] = static_cast<std::uint8_t>(std::clamp(v, 0.0, 255.0));
  }
  const std::size_t n = quick ? 16384 : 262144;
  std::vector<float> in[6];
  for (auto& v : in) v.resize(n);
  std::uniform_real_distribution<float> coord(-3.0f, 4.0f), lod(-2.0f, 7.0f), angle(0.0f, 6.2831853f);
  for (std::size_t i = 0; i < n; ++i) {
    in[0][i] = coord(rng), in[1][i] = coord(rng);
    const float scale = std::exp2(lod(rng)) / kSide, a = angle(rng);  // |d(s w, t h)| = 2^lod
    in[2][i] = scale * std::cos(a), in[3][i] = scale * std::sin(a);
    in[4][i] = -scale * std::sin(a), in[5][i] = scale * std::cos(a);
  }
  struct Filter {
    TextureFilter filter;
    const char* name;
  };
  for (const Filter f : {Filter{TextureFilter::nearest, "nearest"}, Filter{TextureFilter::bilinear, "bilinear"},
                         Filter{TextureFilter::trilinear, "trilinear"}}) {
    TextureOptions options;
    options.filter = f.filter;
    const Result<Texture> t = make_texture("accuracy", kSide, kSide, rgba, options);
    if (!t) continue;
    const texture::Sampler sampler = texture::make_sampler(*t);
    std::vector<double> ref(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const double lambda = texture::lod_reference(sampler, in[2][i], in[3][i], in[4][i], in[5][i]);
      const auto c = texture::sample_reference(sampler, in[0][i], in[1][i], lambda);
      for (int k = 0; k < 4; ++k) ref[4 * i + static_cast<std::size_t>(k)] = c[static_cast<std::size_t>(k)];
    }
    std::vector<float> out[4];
    for (auto& v : out) v.resize(n);
    float* const outs[4] = {out[0].data(), out[1].data(), out[2].data(), out[3].data()};
    const float* const ins[6] = {in[0].data(), in[1].data(), in[2].data(), in[3].data(), in[4].data(), in[5].data()};
    // run() samples every input; unpack() (untimed) leaves the samples in out as floats 0..1.
    auto measure = [&](const std::string& method, const auto& run, const auto& unpack, double max_steps) {
      run();
      unpack();
      Row r;
      r.kind = "texture";
      r.method = method;
      r.item = f.name;
      double sum = 0;
      std::size_t over_one = 0;
      for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 4; ++k) {
          const double e = std::abs(double(out[k][i]) - ref[4 * i + static_cast<std::size_t>(k)]) * 255.0;
          if (std::isnan(e)) ++r.nans;
          r.max_lsb = std::max(r.max_lsb, e);
          sum += e;
          over_one += e > 1.0;
        }
      }
      r.mean_lsb = sum / double(4 * n);
      int reps = 0;
      const auto start = std::chrono::steady_clock::now();
      double seconds = 0;
      do {
        run();
        ++reps;
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      } while (seconds < (quick ? 0.02 : 0.2));
      r.rate = double(n) * reps / seconds;
      // Contract (docs/textures.md): bilinear and trilinear within a step (the 16-bit tier's
      // fixed-point sampler: 1.5 and 2 steps); nearest picks the reference's texel but for
      // coordinates within float rounding of a texel border.
      if (r.nans) {
        r.verdict = "NaN";
      } else if (f.filter == TextureFilter::nearest) {
        r.verdict = double(over_one) <= 1e-3 * double(4 * n) ? "ok" : "nearest: too many other texels";
      } else {
        r.verdict = r.max_lsb <= max_steps ? "ok" : "over " + number(max_steps) + " steps";
      }
      rows.push_back(r);
    };
    const auto nothing = [] {};
    measure("scalar", [&] {
      for (std::size_t i = 0; i < n; ++i) {
        const float lambda = texture::lod_scalar(sampler, in[2][i], in[3][i], in[4][i], in[5][i]);
        const auto c = texture::sample_scalar(sampler, in[0][i], in[1][i], lambda);
        for (int k = 0; k < 4; ++k) out[k][i] = c[static_cast<std::size_t>(k)];
      }
    }, nothing, 1.0);
    std::vector<std::uint32_t> packed(n);
    const double fixed_steps = f.filter == TextureFilter::trilinear ? 2.0 : 1.5;
    const auto unpack = [&] {
      for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 4; ++k) out[k][i] = static_cast<float>((packed[i] >> (8 * k)) & 0xffu) / 255.0f;
      }
    };
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      const tile::simd::Kernels* k = tile::simd_raster_kernels(isa);
      if (!k) continue;
      measure(std::string("simd ") + to_string(isa), [&] { k->sample(sampler, n, ins, outs); }, nothing, 1.0);
      measure(std::string("simd ") + to_string(isa) + " 16-bit", [&] { k->sample_fixed(sampler, n, ins, packed.data()); },
              unpack, fixed_steps);
    }
  }
}

}  // namespace facet::cli
