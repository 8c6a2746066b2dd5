// Internal: image-based lighting for PBR materials, prepared once per environment (and kept by
// the renderer from frame to frame): the split-sum DFG table, the environment's order-2
// spherical harmonics for diffuse light and its radiance prefiltered per roughness into a cube
// map's levels for specular light (Karis 2013). The kernels read it through the lookups below in
// their own precision; everything is built in double from the picture and stored in float.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "facet/environment_light.hpp"
#include "facet/status.hpp"
#include "lighting/pbr.hpp"
#include "lighting/sh9.hpp"

namespace facet::lighting {

// The DFG table's grid is kDfgSize (simd_types.hpp) a side; GGX samples per cell (pbr::DfgTable).
inline constexpr unsigned kDfgSamples = 512;

// The prefiltered cube's kRadianceLevels levels (simd_types.hpp), read linearly between levels:
// faces of size >> k texels a side, at least kRadianceMinSize.
inline constexpr int kRadianceSize = 128;
inline constexpr int kRadianceMinSize = 16;

// The prefilter's choices (what the renderer uses: the defaults; `facet accuracy --only ibl`
// charts the others): the finest level's face size, in [kRadianceMinSize, 512], and the GGX
// samples per texel of the levels above the first rough one, which takes half as many (its narrow
// lobe's samples read finer halvings).
struct PrefilterSettings {
  int size = kRadianceSize;
  unsigned samples = 256;
  unsigned samples_at(int level) const { return level <= 1 ? (samples + 1) / 2 : samples; }
};

// GL's cube face of a direction (GL 2.1 table 3.21): faces +X, -X, +Y, -Y, +Z, -Z and the face
// coordinates s, t in [0, 1]; and back.
template <class T>
[[gnu::always_inline]] inline void cube_face(T x, T y, T z, int& face, T& s, T& t) {
  const T ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
  T sc, tc, ma;
  if (ax >= ay && ax >= az) {
    face = x > T(0) ? 0 : 1, sc = x > T(0) ? -z : z, tc = -y, ma = ax;
  } else if (ay >= az) {
    face = y > T(0) ? 2 : 3, sc = x, tc = y > T(0) ? z : -z, ma = ay;
  } else {
    face = z > T(0) ? 4 : 5, sc = z > T(0) ? x : -x, tc = -y, ma = az;
  }
  const T inv = ma > T(0) ? T(1) / ma : T(0);
  s = T(0.5) * (sc * inv + T(1)), t = T(0.5) * (tc * inv + T(1));
}
V3<double> cube_direction(int face, double s, double t);

// Bilinear at face coordinates (s, t) of `face` (clamped at its edges) of six n x n faces of RGB
// texels, each face's rows of s at increasing t.
template <class T>
[[gnu::always_inline]] inline V3<T> face_bilinear(const float* faces, int n, int face, T s, T t) {
  auto coordinate = [n](T x, int& i, T& f) {
    T c = x * T(n) - T(0.5);
    c = c > T(0) ? (c < T(n - 1) ? c : T(n - 1)) : T(0);
    i = static_cast<int>(c);
    if (i > n - 2) i = n - 2 < 0 ? 0 : n - 2;
    f = c - T(i);
  };
  int i, j;
  T fs, ft;
  coordinate(s, i, fs);
  coordinate(t, j, ft);
  const std::size_t step = n > 1 ? 3 : 0, row = n > 1 ? 3 * std::size_t(n) : 0;
  const float* t00 = faces + std::size_t(face) * std::size_t(n) * std::size_t(n) * 3 + 3 * (std::size_t(j) * std::size_t(n) + std::size_t(i));
  const float* t01 = t00 + row;
  T out[3];
  for (int c = 0; c < 3; ++c) {
    const T a = T(t00[c]) + (T(t00[c + step]) - T(t00[c])) * fs;
    const T b = T(t01[c]) + (T(t01[c + step]) - T(t01[c])) * fs;
    out[c] = a + (b - a) * ft;
  }
  return {out[0], out[1], out[2]};
}

// Bilinear within the face of the direction r.
template <class T>
[[gnu::always_inline]] inline V3<T> cube_sample(const float* faces, int n, V3<T> r) {
  int face;
  T s, t;
  cube_face(r.x, r.y, r.z, face, s, t);
  return face_bilinear(faces, n, face, s, t);
}

// A picture of radiance around the scene, read bilinearly (wrapping in u, clamped in v), with
// its box-filtered halvings for reading a wide cone at once.
struct EquirectLevel {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

class ImageLight {
 public:
  // The DFG table alone (every PBR draw reads it): no environment.
  explicit ImageLight(PrefilterSettings settings = {});
  // Prepares `env` (none: only the table). run(count, fn) calls fn(i) for every i in [0, count),
  // in any order and on any threads; the result is the same. `cancelled` is polled between rows.
  Status build(const EnvironmentLight& env, const std::function<void(std::size_t, const std::function<void(std::size_t)>&)>& run,
               const std::function<bool()>& cancelled = {});
  // build() unless `env`'s picture is what was built already.
  Status prepare(const EnvironmentLight& env, const std::function<void(std::size_t, const std::function<void(std::size_t)>&)>& run,
                 const std::function<bool()>& cancelled = {}) {
    return built_from(env) ? Status{} : build(env, run, cancelled);
  }
  bool has_image() const { return has_image_; }
  // Whether `env`'s picture is what was built (its source, size and texels).
  bool built_from(const EnvironmentLight& env) const;
  // Bytes this light holds (its levels, the source's halvings and the table).
  std::uint64_t bytes() const;
  // At most the bytes a light built from `env` holds (before building it: the memory budget's
  // share of the surroundings).
  static std::uint64_t estimate_bytes(const EnvironmentLight& env);

  // Split-sum terms at (n.v, roughness): scale and bias of f0 and f90.
  template <class T>
  void dfg(T n_dot_v, T roughness, T& scale, T& bias) const {
    auto coordinate = [](T x, int& k, T& f) {
      T c = x * T(kDfgSize) - T(0.5);
      c = c > T(0) ? (c < T(kDfgSize - 1) ? c : T(kDfgSize - 1)) : T(0);  // NaN -> 0
      k = static_cast<int>(c);
      if (k > kDfgSize - 2) k = kDfgSize - 2;
      f = c - T(k);
    };
    int i, j;
    T s, t;
    coordinate(n_dot_v, i, s);
    coordinate(roughness, j, t);
    const float* c00 = &dfg_[2 * (j * kDfgSize + i)];
    const float* c01 = c00 + 2 * kDfgSize;
    for (int k = 0; k < 2; ++k) {
      const T a = T(c00[k]) + (T(c00[k + 2]) - T(c00[k])) * s;
      const T b = T(c01[k]) + (T(c01[k + 2]) - T(c01[k])) * s;
      (k == 0 ? scale : bias) = a + (b - a) * t;
    }
  }
  // Diffuse: irradiance / pi at the unit world-space normal n (the radiance a white Lambertian
  // surface shows), from the harmonics; >= 0.
  template <class T>
  V3<T> diffuse(V3<T> n) const {
    const T x = n.x, y = n.y, z = n.z;
    const T y9[9] = {T(1), y, z, x, x * y, y * z, T(3) * z * z - T(1), x * z, x * x - y * y};
    T out[3];
    for (int c = 0; c < 3; ++c) {
      T e = T(0);
      for (int k = 0; k < 9; ++k) e += T(sh_[c][k]) * y9[k];
      out[c] = e > T(0) ? e : T(0);
    }
    return {out[0], out[1], out[2]};
  }
  // Specular: the radiance prefiltered for `roughness` around the unit world-space direction r.
  template <class T>
  V3<T> specular(V3<T> r, T roughness) const {
    T level = roughness * T(kRadianceLevels - 1);
    level = level > T(0) ? (level < T(kRadianceLevels - 1) ? level : T(kRadianceLevels - 1)) : T(0);
    const int k = level < T(kRadianceLevels - 1) ? static_cast<int>(level) : kRadianceLevels - 2;
    const T f = level - T(k);
    const V3<T> a = cube_bilinear(k, r), b = cube_bilinear(k + 1, r);
    return {a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f, a.z + (b.z - a.z) * f};
  }

  // What the SIMD kernels read (valid while this light is neither rebuilt nor destroyed).
  simd::ImageView view() const;
  // The source's radiance (level 0 of the halvings), bilinear, at a unit direction (the tests'
  // brute-force integrals read the same picture the prefilter read).
  V3<double> source(const V3<double>& d, double lod = 0.0) const;
  // The picture itself at a unit direction, bilinear at full resolution, in float: what the
  // backdrop (Scene::background) shows, read once per uncovered pixel; (0, 0, 0) without one.
  V3<float> picture(float x, float y, float z) const;

 private:
  template <class T>
  V3<T> cube_bilinear(int k, V3<T> r) const {
    return cube_sample(radiance_.data() + offsets_[k], sizes_[k], r);
  }
  // The radiance the prefilter reads: the picture as a cube with its halvings, at a level of detail.
  V3<double> cube_source(const V3<double>& d, double lod) const;

  std::vector<float> dfg_;  // kDfgSize^2 cells of (scale, bias), n.v fastest
  bool has_image_ = false;
  float sh_[3][9] = {};     // per channel: A_l L_lm / pi times each basis function's constant
  PrefilterSettings settings_;
  int sizes_[kRadianceLevels] = {};
  std::size_t offsets_[kRadianceLevels] = {};
  std::vector<float> radiance_;  // the levels one after another: 6 faces of size^2 RGB texels, t rows of s
  std::vector<EquirectLevel> source_;           // the picture and its halvings
  std::vector<std::vector<float>> source_cube_;  // the picture as a cube (source_cube_size_ texels a side) and its halvings
  int source_cube_size_ = 0;
  // What was built (built_from): the source and its picture (intensity and rotation are the
  // kernels' to apply, so that turning the surroundings rebuilds nothing).
  EnvironmentSource source_kind_ = EnvironmentSource::none;
  int width_ = 0, height_ = 0;
};

// facet's neutral studio as an equirectangular picture of width x height (docs/pbr.md).
EquirectLevel make_studio(int width, int height);

}  // namespace facet::lighting
