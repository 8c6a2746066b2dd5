#include "lighting/image_light.hpp"

#include <algorithm>
#include <cstring>
#include <numbers>

namespace facet::lighting {
namespace {

constexpr double kPi = std::numbers::pi;

// The equirectangular coordinates (u, v) of a unit direction, v = 1 the top row.
void equirect_uv(const V3<double>& d, double& u, double& v) {
  u = 0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi);
  v = 0.5 + std::asin(std::clamp(d.y, -1.0, 1.0)) / kPi;
}

V3<double> bilinear(const EquirectLevel& l, double u, double v) {
  const double x = u * l.width - 0.5, y = (1.0 - v) * l.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double sx = x - fx, sy = y - fy;
  auto texel = [&](long i, long j) {
    i = ((i % l.width) + l.width) % l.width;
    j = std::clamp<long>(j, 0, l.height - 1);
    const float* t = l.rgb.data() + 3 * (std::size_t(j) * std::size_t(l.width) + std::size_t(i));
    return V3<double>{t[0], t[1], t[2]};
  };
  const long i = static_cast<long>(fx), j = static_cast<long>(fy);
  const V3<double> a = (1.0 - sx) * texel(i, j) + sx * texel(i + 1, j);
  const V3<double> b = (1.0 - sx) * texel(i, j + 1) + sx * texel(i + 1, j + 1);
  return (1.0 - sy) * a + sy * b;
}

EquirectLevel halve(const EquirectLevel& l) {
  EquirectLevel h;
  h.width = std::max(1, l.width / 2), h.height = std::max(1, l.height / 2);
  h.rgb.resize(std::size_t(h.width) * std::size_t(h.height) * 3);
  for (int j = 0; j < h.height; ++j) {
    for (int i = 0; i < h.width; ++i) {
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        int n = 0;
        for (int dj = 0; dj < 2; ++dj) {
          for (int di = 0; di < 2; ++di) {
            const int x = std::min(2 * i + di, l.width - 1), y = std::min(2 * j + dj, l.height - 1);
            sum += l.rgb[3 * (std::size_t(y) * std::size_t(l.width) + std::size_t(x)) + std::size_t(c)];
            ++n;
          }
        }
        h.rgb[3 * (std::size_t(j) * std::size_t(h.width) + std::size_t(i)) + std::size_t(c)] = float(sum / n);
      }
    }
  }
  return h;
}

// A soft-edged rectangular panel around the unit direction `centre`: 1 inside half-widths (w, h)
// radians of its frame, falling to 0 over the outer fifth.
double panel(const V3<double>& d, const V3<double>& centre, double w, double h) {
  const double c = dot(d, centre);
  if (c <= 0.0) return 0.0;
  const V3<double> up = std::abs(centre.y) < 0.99 ? V3<double>{0.0, 1.0, 0.0} : V3<double>{0.0, 0.0, 1.0};
  V3<double> right{up.y * centre.z - up.z * centre.y, up.z * centre.x - up.x * centre.z, up.x * centre.y - up.y * centre.x};
  right = (1.0 / std::sqrt(dot(right, right))) * right;
  const V3<double> top{centre.y * right.z - centre.z * right.y, centre.z * right.x - centre.x * right.z,
                       centre.x * right.y - centre.y * right.x};
  const double x = std::abs(std::atan2(dot(d, right), c)) / w, y = std::abs(std::atan2(dot(d, top), c)) / h;
  auto edge = [](double t) { return std::clamp((1.0 - t) / 0.2, 0.0, 1.0); };
  return edge(x) * edge(y);
}

V3<double> unit(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  return {x / l, y / l, z / l};
}

}  // namespace

V3<double> cube_direction(int face, double s, double t) {
  const double sc = 2.0 * s - 1.0, tc = 2.0 * t - 1.0;
  V3<double> d{};
  switch (face) {
    case 0: d = {1.0, -tc, -sc}; break;
    case 1: d = {-1.0, -tc, sc}; break;
    case 2: d = {sc, 1.0, tc}; break;
    case 3: d = {sc, -1.0, -tc}; break;
    case 4: d = {sc, -tc, 1.0}; break;
    default: d = {-sc, -tc, -1.0}; break;
  }
  return (1.0 / std::sqrt(dot(d, d))) * d;
}

EquirectLevel make_studio(int width, int height) {
  EquirectLevel out;
  out.width = width, out.height = height;
  out.rgb.resize(std::size_t(width) * std::size_t(height) * 3);
  // The panels (a key above the camera's left, a fill to its right, a strip overhead and a rim
  // behind), in world space with the camera's default side at +Z; radiance in linear units.
  struct Panel {
    V3<double> centre;
    double w, h, radiance;
  };
  // World directions w, placed where the kernels look them up: (w.z, w.y, -w.x) (setup.cpp's
  // quarter turn from three.js's reading of a picture to the image light's).
  auto at = [](double x, double y, double z) { return unit(z, y, -x); };
  const Panel panels[] = {{at(-0.7, 0.55, 0.6), 0.45, 0.3, 6.0},
                          {at(0.85, 0.15, 0.5), 0.35, 0.45, 2.0},
                          {at(0.0, 1.0, 0.0), 0.5, 0.2, 4.0},
                          {at(0.35, 0.3, -0.9), 0.3, 0.35, 3.0}};
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const V3<double> d = sh9::equirect_direction(c, r, width, height);
      // A dim room: a darker floor, a lighter ceiling, a soft horizon between.
      const double t = std::clamp(0.5 + 0.5 * d.y, 0.0, 1.0);
      double l = 0.06 + 0.22 * t * t;
      for (const Panel& p : panels) l += p.radiance * panel(d, p.centre, p.w, p.h);
      float* o = out.rgb.data() + 3 * (std::size_t(r) * std::size_t(width) + std::size_t(c));
      o[0] = o[1] = o[2] = float(l);
    }
  }
  return out;
}

ImageLight::ImageLight(PrefilterSettings settings) : settings_(settings) {
  settings_.size = std::clamp(settings_.size, kRadianceMinSize, 512);
  settings_.samples = std::clamp(settings_.samples, 2u, 1u << 16);
  const pbr::DfgTable table(kDfgSize, kDfgSamples);
  dfg_.resize(2 * kDfgSize * kDfgSize);
  for (int j = 0; j < kDfgSize; ++j) {
    for (int i = 0; i < kDfgSize; ++i) {
      const pbr::Dfg d = table.at((i + 0.5) / kDfgSize, (j + 0.5) / kDfgSize);
      dfg_[std::size_t(2 * (j * kDfgSize + i))] = float(d.scale);
      dfg_[std::size_t(2 * (j * kDfgSize + i) + 1)] = float(d.bias);
    }
  }
}

bool ImageLight::built_from(const EnvironmentLight& env) const {
  if (env.source != source_kind_) return false;
  if (env.source != EnvironmentSource::image) return true;
  // The picture against the copy the light keeps (its first level): a compare of memory, a small
  // part of a frame, where a hash of the texels was a quarter of a small model's warm frame.
  if (env.width != width_ || env.height != height_ || source_.empty() || env.rgb.size() != source_[0].rgb.size()) return false;
  return env.rgb.empty() || std::memcmp(env.rgb.data(), source_[0].rgb.data(), env.rgb.size() * sizeof(float)) == 0;
}

std::uint64_t ImageLight::bytes() const {
  std::uint64_t n = dfg_.size() * sizeof(float);
  n += radiance_.size() * sizeof(float);
  for (const auto& l : source_) n += l.rgb.size() * sizeof(float);
  for (const auto& l : source_cube_) n += l.size() * sizeof(float);
  return n;
}

std::uint64_t ImageLight::estimate_bytes(const EnvironmentLight& env) {
  std::uint64_t n = std::uint64_t(kDfgSize) * kDfgSize * 2 * sizeof(float);
  if (env.source == EnvironmentSource::none) return n;
  const std::uint64_t w = env.source == EnvironmentSource::studio ? 256 : std::uint64_t(std::max(env.width, 1));
  const std::uint64_t h = env.source == EnvironmentSource::studio ? 128 : std::uint64_t(std::max(env.height, 1));
  n += w * h * 3 * sizeof(float) * 4 / 3 + 64 * 1024;  // the picture and its halvings (rounding up)
  const std::uint64_t cube = std::uint64_t(std::clamp(int(h / 2), 8, 256));
  n += 6 * cube * cube * 3 * sizeof(float) * 4 / 3 + 6 * 3 * sizeof(float) * 64;  // the source cube and its halvings
  for (int level = 0; level < kRadianceLevels; ++level) {
    const std::uint64_t side = std::uint64_t(std::max(kRadianceMinSize, kRadianceSize >> level));
    n += 6 * side * side * 3 * sizeof(float);
  }
  return n;
}

V3<double> ImageLight::cube_source(const V3<double>& d, double lod) const {
  lod = std::clamp(lod, 0.0, double(source_cube_.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(lod), source_cube_.size() - 1);
  const double f = lod - double(k);
  const V3<double> a = cube_sample(source_cube_[k].data(), std::max(1, source_cube_size_ >> k), d);
  if (f <= 0.0 || k + 1 >= source_cube_.size()) return a;
  return (1.0 - f) * a + f * cube_sample(source_cube_[k + 1].data(), std::max(1, source_cube_size_ >> (k + 1)), d);
}

namespace {

// atan2(y, x) within 1e-5 radians (Hastings' odd polynomial for atan on [-1, 1], the octants by
// symmetry): a thousandth of a texel of an 8192-texel-wide picture, at a fraction of libm's cost.
// atan2(0, 0) = 0.
float atan2_fast(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float lo = std::min(ax, ay), hi = std::max(ax, ay);
  const float t = hi > 0.0f ? lo / hi : 0.0f, t2 = t * t;
  float a = t * (0.99997726f + t2 * (-0.33262347f + t2 * (0.19354346f + t2 * (-0.11643287f + t2 * (0.05265332f + t2 * -0.01172120f)))));
  if (ay > ax) a = 1.57079633f - a;
  if (x < 0.0f) a = 3.14159265f - a;
  return y < 0.0f ? -a : a;
}

}  // namespace

V3<float> ImageLight::picture(float x, float y, float z) const {
  if (source_.empty()) return {0.0f, 0.0f, 0.0f};
  const EquirectLevel& l = source_[0];
  // equirect_uv and bilinear in float, the wrap and clamp without divisions.
  const float yc = std::clamp(y, -1.0f, 1.0f);
  const float u = 0.5f + atan2_fast(x, -z) * float(0.5 / kPi), v = 0.5f + atan2_fast(yc, std::sqrt(1.0f - yc * yc)) * float(1.0 / kPi);
  const float fx = u * float(l.width) - 0.5f, fy = (1.0f - v) * float(l.height) - 0.5f;
  const float x0 = std::floor(fx), y0 = std::floor(fy);
  const float sx = fx - x0, sy = fy - y0;
  int i0 = static_cast<int>(x0), j0 = static_cast<int>(y0);
  if (i0 < 0) i0 += l.width;  // u in [0, 1]: at most one width out either side
  if (i0 >= l.width) i0 -= l.width;
  const int i1 = i0 + 1 < l.width ? i0 + 1 : 0;
  const int j1 = std::clamp(j0 + 1, 0, l.height - 1);
  j0 = std::clamp(j0, 0, l.height - 1);
  const float* r0 = l.rgb.data() + 3 * std::size_t(j0) * std::size_t(l.width);
  const float* r1 = l.rgb.data() + 3 * std::size_t(j1) * std::size_t(l.width);
  float out[3];
  for (int c = 0; c < 3; ++c) {
    const float a = r0[3 * i0 + c] + (r0[3 * i1 + c] - r0[3 * i0 + c]) * sx;
    const float b = r1[3 * i0 + c] + (r1[3 * i1 + c] - r1[3 * i0 + c]) * sx;
    out[c] = a + (b - a) * sy;
  }
  return {out[0], out[1], out[2]};
}

V3<double> ImageLight::source(const V3<double>& d, double lod) const {
  if (source_.empty()) return {0.0, 0.0, 0.0};
  double u, v;
  equirect_uv(d, u, v);
  lod = std::clamp(lod, 0.0, double(source_.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(lod), source_.size() - 1);
  const double f = lod - double(k);
  const V3<double> a = bilinear(source_[k], u, v);
  if (f <= 0.0 || k + 1 >= source_.size()) return a;
  return (1.0 - f) * a + f * bilinear(source_[k + 1], u, v);
}

Status ImageLight::build(const EnvironmentLight& env,
                         const std::function<void(std::size_t, const std::function<void(std::size_t)>&)>& run,
                         const std::function<bool()>& cancelled) {
  has_image_ = false;
  source_.clear();
  source_cube_.clear();
  radiance_.clear();
  std::memset(sh_, 0, sizeof sh_);
  source_kind_ = env.source, width_ = env.width, height_ = env.height;
  if (env.source == EnvironmentSource::none) return {};
  if (env.source == EnvironmentSource::studio) {
    source_.push_back(make_studio(256, 128));
  } else {
    for (std::size_t i = 0; i < env.rgb.size(); ++i) {
      if (!(env.rgb[i] >= 0.0f && env.rgb[i] <= 3.4e38f)) {
        source_kind_ = EnvironmentSource::none;
        return {ErrorCode::invalid_argument, "environment_light.rgb",
                "environment_light.rgb: texel " + std::to_string(i / 3) + " holds a negative, infinite or NaN value"};
      }
    }
    source_.push_back(EquirectLevel{env.width, env.height, env.rgb});
  }
  while (source_.back().width > 8 && source_.back().height > 4) source_.push_back(halve(source_.back()));
  // Harmonics from the widest halving at most 512 texels wide (they hold nothing finer).
  std::size_t project_from = 0;
  while (project_from + 1 < source_.size() && source_[project_from].width > 512) ++project_from;
  const EquirectLevel& p = source_[project_from];
  const sh9::Coefficients sh = sh9::project_equirect(p.rgb.data(), p.width, p.height);
  // diffuse() = sum of (A_l / pi) L_lm Y_lm: the basis functions' constants folded in here.
  const double a[9] = {1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25};
  const double k[9] = {0.28209479177387814, 0.4886025119029199, 0.4886025119029199, 0.4886025119029199,
                       1.0925484305920792,  1.0925484305920792, 0.31539156525252005, 1.0925484305920792,
                       0.5462742152960396};
  for (int i = 0; i < 9; ++i) {
    sh_[0][i] = float(a[i] * k[i] * sh[std::size_t(i)].x);
    sh_[1][i] = float(a[i] * k[i] * sh[std::size_t(i)].y);
    sh_[2][i] = float(a[i] * k[i] * sh[std::size_t(i)].z);
  }
  // The picture as a cube of about its own resolution (at most 256 a side), read at the level of
  // the halvings that matches a cube texel, and the cube's halvings: what the prefilter samples
  // (no trigonometry per sample).
  source_cube_size_ = std::clamp(source_[0].height / 2, 8, 256);
  source_cube_.clear();
  {
    const int n = source_cube_size_;
    std::vector<float> base(std::size_t(6) * std::size_t(n) * std::size_t(n) * 3);
    const double lod = std::max(0.0, 0.5 * std::log2((4.0 * kPi / (6.0 * n * n)) /
                                                      (4.0 * kPi / (double(source_[0].width) * double(source_[0].height)))));
    run(std::size_t(6) * std::size_t(n), [&](std::size_t row) {
      const int face = int(row / std::size_t(n)), j = int(row % std::size_t(n));
      for (int i = 0; i < n; ++i) {
        const V3<double> v = source(cube_direction(face, (i + 0.5) / n, (j + 0.5) / n), lod);
        float* o = base.data() + 3 * ((std::size_t(face) * std::size_t(n) + std::size_t(j)) * std::size_t(n) + std::size_t(i));
        o[0] = float(v.x), o[1] = float(v.y), o[2] = float(v.z);
      }
    });
    source_cube_.push_back(std::move(base));
    for (int m = n / 2; m >= 1; m /= 2) {
      const std::vector<float>& up = source_cube_.back();
      const int u = 2 * m;
      std::vector<float> down(std::size_t(6) * std::size_t(m) * std::size_t(m) * 3);
      for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < m; ++j) {
          for (int i = 0; i < m; ++i) {
            for (int c = 0; c < 3; ++c) {
              auto at = [&](int x, int y) { return up[3 * ((std::size_t(face) * u + std::size_t(y)) * u + std::size_t(x)) + std::size_t(c)]; };
              down[3 * ((std::size_t(face) * m + std::size_t(j)) * m + std::size_t(i)) + std::size_t(c)] =
                  0.25f * (at(2 * i, 2 * j) + at(2 * i + 1, 2 * j) + at(2 * i, 2 * j + 1) + at(2 * i + 1, 2 * j + 1));
            }
          }
        }
      }
      source_cube_.push_back(std::move(down));
    }
  }
  // The prefiltered levels, one face row per task.
  const double texel0 = 4.0 * kPi / (6.0 * double(source_cube_size_) * double(source_cube_size_));
  bool stop = false;
  std::size_t floats = 0;
  for (int level = 0; level < kRadianceLevels; ++level) {
    sizes_[level] = std::max(kRadianceMinSize, settings_.size >> level);
    offsets_[level] = floats;
    floats += std::size_t(6) * std::size_t(sizes_[level]) * std::size_t(sizes_[level]) * 3;
  }
  radiance_.assign(floats, 0.0f);
  for (int level = 0; level < kRadianceLevels && !stop; ++level) {
    const int n = sizes_[level];
    float* const out = radiance_.data() + offsets_[level];
    const double roughness = double(level) / (kRadianceLevels - 1);
    const double alpha = pbr::alpha_of(roughness);
    const double cube_texel = 4.0 * kPi / (6.0 * n * n);
    // The level's GGX samples around +z, once: each half vector, its weight n.l (samples below
    // the horizon dropped) and the two halvings its light is read from, with the blend between.
    struct Sample {
      float hx, hy, hz, weight, blend;
      int k;
    };
    std::vector<Sample> samples;
    double weight = 0.0;
    const int halvings = int(source_cube_.size());
    if (level > 0) {
      const unsigned count = settings_.samples_at(level);
      for (unsigned s = 0; s < count; ++s) {
        const V3<double> hs = pbr::ggx_sample(s, count, alpha);
        const double n_dot_l = 2.0 * hs.z * hs.z - 1.0;
        if (n_dot_l <= 0.0) continue;
        const double pdf = pbr::ggx_d(hs.z, alpha) / 4.0;  // of l, with n = v = r
        const double lod = std::clamp(0.5 * std::log2(1.0 / (count * pdf * texel0)), 0.0, double(halvings - 1));
        const int k = std::min(static_cast<int>(lod), std::max(0, halvings - 2));
        samples.push_back({float(hs.x), float(hs.y), float(hs.z), float(n_dot_l), float(std::min(1.0, lod - k)), k});
        weight += n_dot_l;
      }
    }
    run(std::size_t(6) * std::size_t(n), [&](std::size_t row) {
      if (cancelled && cancelled()) return;
      const int face = int(row / std::size_t(n)), j = int(row % std::size_t(n));
      for (int i = 0; i < n; ++i) {
        const V3<double> r = cube_direction(face, (i + 0.5) / n, (j + 0.5) / n);
        V3<double> value;
        if (level == 0) {  // a mirror: the picture itself, read at the cube texel's size
          value = cube_source(r, std::max(0.0, 0.5 * std::log2(cube_texel / texel0)));
        } else {
          // GGX-weighted radiance around r (pbr::prefiltered), each sample read from the halving
          // whose texel matches the sample's share of the lobe (Colbert and Krivanek 2007).
          const V3<double> up = std::abs(r.z) < 0.999 ? V3<double>{0.0, 0.0, 1.0} : V3<double>{1.0, 0.0, 0.0};
          V3<double> t{up.y * r.z - up.z * r.y, up.z * r.x - up.x * r.z, up.x * r.y - up.y * r.x};
          t = (1.0 / std::sqrt(dot(t, t))) * t;
          const V3<double> b{r.y * t.z - r.z * t.y, r.z * t.x - r.x * t.z, r.x * t.y - r.y * t.x};
          const V3<float> tf{float(t.x), float(t.y), float(t.z)}, bf{float(b.x), float(b.y), float(b.z)},
              rf{float(r.x), float(r.y), float(r.z)};
          double sum[3] = {0.0, 0.0, 0.0};
          for (const Sample& sm : samples) {
            const float h[3] = {sm.hx * tf.x + sm.hy * bf.x + sm.hz * rf.x, sm.hx * tf.y + sm.hy * bf.y + sm.hz * rf.y,
                                sm.hx * tf.z + sm.hy * bf.z + sm.hz * rf.z};
            const float two = 2.0f * sm.hz;
            const V3<float> l{two * h[0] - rf.x, two * h[1] - rf.y, two * h[2] - rf.z};
            const int k = sm.k, m = std::min(k + 1, halvings - 1);
            int face_of_l;
            float s, t;
            cube_face(l.x, l.y, l.z, face_of_l, s, t);
            const V3<float> a = face_bilinear(source_cube_[std::size_t(k)].data(), std::max(1, source_cube_size_ >> k), face_of_l, s, t);
            const V3<float> c = face_bilinear(source_cube_[std::size_t(m)].data(), std::max(1, source_cube_size_ >> m), face_of_l, s, t);
            sum[0] += sm.weight * (a.x + (c.x - a.x) * sm.blend);
            sum[1] += sm.weight * (a.y + (c.y - a.y) * sm.blend);
            sum[2] += sm.weight * (a.z + (c.z - a.z) * sm.blend);
          }
          value = {sum[0] / weight, sum[1] / weight, sum[2] / weight};
        }
        float* o = out + 3 * ((std::size_t(face) * std::size_t(n) + std::size_t(j)) * std::size_t(n) + std::size_t(i));
        o[0] = float(value.x), o[1] = float(value.y), o[2] = float(value.z);
      }
    });
    stop = cancelled && cancelled();
  }
  if (stop) {
    source_kind_ = EnvironmentSource::none;  // half built: never reused
    return {ErrorCode::cancelled, "environment_image", "environment_image: prefiltering was cancelled"};
  }
  has_image_ = true;
  return {};
}

simd::ImageView ImageLight::view() const {
  simd::ImageView v;
  v.dfg = dfg_.data();
  v.has_image = has_image_ ? 1 : 0;
  std::memcpy(v.sh, sh_, sizeof sh_);
  v.radiance = radiance_.data();
  for (int k = 0; k < kRadianceLevels; ++k) {
    v.offset[k] = static_cast<int>(offsets_[k]);
    v.size[k] = sizes_[k];
  }
  return v;
}

}  // namespace facet::lighting

namespace facet {

const char* to_string(Background background) noexcept {
  switch (background) {
    case Background::colour: return "colour";
    case Background::environment: return "environment";
  }
  return "?";
}

const char* to_string(EnvironmentSource source) noexcept {
  switch (source) {
    case EnvironmentSource::none: return "none";
    case EnvironmentSource::studio: return "studio";
    case EnvironmentSource::image: return "image";
  }
  return "?";
}

}  // namespace facet
