// The scalar float sampler (the SIMD sampler's twin) and the double-precision reference sampler;
// see sampler.hpp for the arithmetic both follow. Built with -ffp-contract=off, as the raster kernels.
#include "texture/sampler.hpp"

#include "texture/srgb_table.hpp"

#include <cfloat>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace facet::texture {
namespace {

constexpr int kRepeat = static_cast<int>(TextureWrap::repeat);
constexpr int kMirror = static_cast<int>(TextureWrap::mirror);
constexpr int kTrilinear = static_cast<int>(TextureFilter::trilinear);
constexpr int kNearest = static_cast<int>(TextureFilter::nearest);
constexpr float kInv255 = 1.0f / 255.0f;

template <class T>
T wrap_coordinate(T s, int wrap) {
  if (wrap == kRepeat) {
    const T r = s - std::floor(s);
    return r >= T(0) && r < T(1) ? r : T(0);
  }
  if (wrap == kMirror) {
    const T r = s - T(2) * std::floor(s * T(0.5));
    return r >= T(0) && r < T(2) ? r : T(0);
  }
  return s > T(0) ? (s < T(1) ? s : T(1)) : T(0);
}

int fold(int i, int n, int wrap) {
  if (wrap == kRepeat) {
    if (i < 0) i += n;
    if (i >= n) i -= n;
  } else if (wrap == kMirror) {
    if (i < 0) i += 2 * n;
    if (i >= 2 * n) i -= 2 * n;
    if (i >= n) i = 2 * n - 1 - i;
  } else {
    i = i < 0 ? 0 : (i >= n ? n - 1 : i);
  }
  return i;
}

// Channel c as 0..255: the stored byte, or for an sRGB texture's colour channels 255 x its decoding
// (the float samplers from the table, the reference in double).
template <class T>
T channel(std::uint32_t texel, int c, const float* decode) {
  const std::uint32_t v = (texel >> (8 * c)) & 0xffu;
  if (decode && c < 3) {
    if constexpr (std::is_same_v<T, float>) {
      return decode[v];
    } else {
      const double x = v / 255.0;
      return 255.0 * (x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
    }
  }
  return static_cast<T>(v);
}

// 0..255 to 0..1: the float samplers multiply by the float 1/255 (as the SIMD twin), the reference divides.
template <class T>
T unit(T x) {
  if constexpr (std::is_same_v<T, float>) {
    return x * kInv255;
  } else {
    return x / 255.0;
  }
}

std::uint32_t texel_at(const SamplerLevel& l, int i, int j) {
  return l.texels[static_cast<std::size_t>(j) * static_cast<std::size_t>(l.width) + static_cast<std::size_t>(i)];
}

// One level, nearest or bilinear, in T (float: the twin of the SIMD sampler; double: the reference).
template <class T>
std::array<T, 4> sample_level(const SamplerLevel& l, int wrap, bool linear, T s, T t, const float* decode) {
  const T fw = static_cast<T>(l.fwidth), fh = static_cast<T>(l.fheight);
  const T rs = wrap_coordinate(s, wrap), rt = wrap_coordinate(t, wrap);
  std::array<T, 4> out{};
  if (!linear) {
    const int i = fold(static_cast<int>(std::floor(rs * fw)), l.width, wrap);
    const int j = fold(static_cast<int>(std::floor(rt * fh)), l.height, wrap);
    const std::uint32_t t00 = texel_at(l, i, j);
    for (int c = 0; c < 4; ++c) out[c] = unit(channel<T>(t00, c, decode));
    return out;
  }
  const T x = rs * fw - T(0.5), y = rt * fh - T(0.5);
  const T fx = std::floor(x), fy = std::floor(y);
  const T a = x - fx, b = y - fy;
  const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy);
  const int i1 = fold(i0 + 1, l.width, wrap), j1 = fold(j0 + 1, l.height, wrap);
  const int ia = fold(i0, l.width, wrap), ja = fold(j0, l.height, wrap);
  const std::uint32_t t00 = texel_at(l, ia, ja), t10 = texel_at(l, i1, ja);
  const std::uint32_t t01 = texel_at(l, ia, j1), t11 = texel_at(l, i1, j1);
  const T ra = T(1) - a, rb = T(1) - b;
  for (int c = 0; c < 4; ++c) {
    const T top = channel<T>(t00, c, decode) * ra + channel<T>(t10, c, decode) * a;
    const T bottom = channel<T>(t01, c, decode) * ra + channel<T>(t11, c, decode) * a;
    out[c] = unit(top * rb + bottom * b);
  }
  return out;
}

// The levels a trilinear sample at LOD lambda > 0 reads, q being the last level: k, and the
// fraction l - k towards k + 1 (k >= q: the last level alone). The rule of the SIMD samplers'
// choose_levels, one lane; the float and the fixed-point samplers both read it.
template <class T>
struct LevelChoice {
  int k;
  T fraction;
};
template <class T>
LevelChoice<T> choose_levels(T lambda, int q) {
  const T l = lambda < T(q) ? lambda : T(q);
  const T d1 = std::floor(l);
  return {static_cast<int>(d1), l - d1};
}

template <class T>
std::array<T, 4> sample(const Sampler& s, T u, T v, T lambda) {
  if (s.filter != kTrilinear || !(lambda > T(0))) return sample_level<T>(s.level[0], s.wrap, s.filter != kNearest, u, v, s.decode);
  const int q = s.levels - 1;
  const auto [k, f] = choose_levels(lambda, q);
  if (k >= q) return sample_level<T>(s.level[q], s.wrap, true, u, v, s.decode);
  const std::array<T, 4> c1 = sample_level<T>(s.level[k], s.wrap, true, u, v, s.decode);
  const std::array<T, 4> c2 = sample_level<T>(s.level[k + 1], s.wrap, true, u, v, s.decode);
  std::array<T, 4> out{};
  for (int c = 0; c < 4; ++c) out[c] = c1[c] * (T(1) - f) + c2[c] * f;
  return out;
}

// One level of the fixed-point sampler (sampler.hpp): nearest, or bilinear in 8.8 fixed point.
std::uint32_t fixed_level(const SamplerLevel& l, int wrap, bool linear, float rs, float rt) {
  if (!linear) {
    const int i = fold(static_cast<int>(std::floor(rs * l.fwidth)), l.width, wrap);
    const int j = fold(static_cast<int>(std::floor(rt * l.fheight)), l.height, wrap);
    return texel_at(l, i, j);
  }
  const int x = static_cast<int>(std::floor(rs * (l.fwidth * 256.0f) - 127.5f));
  const int y = static_cast<int>(std::floor(rt * (l.fheight * 256.0f) - 127.5f));
  const int i0 = x >> 8, j0 = y >> 8;  // arithmetic: floor(x / 256)
  const auto fx = static_cast<std::uint32_t>(x & 255), fy = static_cast<std::uint32_t>(y & 255);
  const int ia = fold(i0, l.width, wrap), ib = fold(i0 + 1, l.width, wrap);
  const int ja = fold(j0, l.height, wrap), jb = fold(j0 + 1, l.height, wrap);
  const std::uint32_t top = lerp_bytes(texel_at(l, ia, ja), texel_at(l, ib, ja), fx);
  const std::uint32_t bottom = lerp_bytes(texel_at(l, ia, jb), texel_at(l, ib, jb), fx);
  return lerp_bytes(top, bottom, fy);
}

}  // namespace

std::uint32_t lerp_bytes(std::uint32_t a, std::uint32_t b, std::uint32_t w) noexcept {
  std::uint32_t out = 0;
  for (int c = 0; c < 4; ++c) {
    const std::uint32_t ac = (a >> (8 * c)) & 0xffu, bc = (b >> (8 * c)) & 0xffu;
    out |= ((ac * (256u - w) + bc * w + 128u) >> 8) << (8 * c);
  }
  return out;
}

std::uint32_t sample_fixed_scalar(const Sampler& s, float u, float v, float lambda) noexcept {
  const float rs = wrap_coordinate(u, s.wrap), rt = wrap_coordinate(v, s.wrap);
  if (s.filter != kTrilinear || !(lambda > 0.0f)) return fixed_level(s.level[0], s.wrap, s.filter != kNearest, rs, rt);
  const int q = s.levels - 1;
  const auto [k, fraction] = choose_levels(lambda, q);
  if (k >= q) return fixed_level(s.level[q], s.wrap, true, rs, rt);
  const auto w = static_cast<std::uint32_t>(static_cast<int>(fraction * 256.0f));
  return lerp_bytes(fixed_level(s.level[k], s.wrap, true, rs, rt), fixed_level(s.level[k + 1], s.wrap, true, rs, rt), w);
}

Sampler make_sampler(const Texture& texture) noexcept {
  Sampler s{};
  s.filter = static_cast<std::int32_t>(texture.filter);
  s.wrap = static_cast<std::int32_t>(texture.wrap);
  s.levels = static_cast<std::int32_t>(texture.levels.size() < kMaxLevels ? texture.levels.size() : kMaxLevels);
  s.lod_width = static_cast<float>(texture.width());
  s.lod_height = static_cast<float>(texture.height());
  for (int k = 0; k < s.levels; ++k) {
    const TextureLevel& l = texture.levels[static_cast<std::size_t>(k)];
    s.level[k] = {texture.texels.data() + l.offset, l.width, l.height, static_cast<float>(l.width),
                  static_cast<float>(l.height)};
    s.width[k] = l.width, s.height[k] = l.height, s.offset[k] = static_cast<std::int32_t>(l.offset);
    s.fwidth[k] = static_cast<float>(l.width), s.fheight[k] = static_cast<float>(l.height);
  }
  s.texels = texture.texels.data();
  s.decode = texture.encoding == TextureEncoding::srgb ? kSrgbDecode255 : nullptr;
  return s;
}

float log2_approx(float x) noexcept {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  const int e = static_cast<int>(bits >> 23) - 127;
  const std::uint32_t mbits = (bits & 0x7fffffu) | 0x3f800000u;
  float m = 0.0f;
  std::memcpy(&m, &mbits, sizeof m);
  m = m - 1.0f;
  float p = kLog2Poly[4];
  p = p * m + kLog2Poly[3];
  p = p * m + kLog2Poly[2];
  p = p * m + kLog2Poly[1];
  p = p * m + kLog2Poly[0];
  return static_cast<float>(e) + p * m;
}

float lod_scalar(const Sampler& s, float dsdx, float dtdx, float dsdy, float dtdy) noexcept {
  const float ax = dsdx * s.lod_width, bx = dtdx * s.lod_height;
  const float ay = dsdy * s.lod_width, by = dtdy * s.lod_height;
  const float px = ax * ax + bx * bx, py = ay * ay + by * by;
  const float rho2 = px > py ? px : py;
  if (!(rho2 >= FLT_MIN)) return -1.0f;  // zero, subnormal or NaN: magnification
  if (rho2 > FLT_MAX) return kFarLod;
  return 0.5f * log2_approx(rho2);
}

double lod_reference(const Sampler& s, double dsdx, double dtdx, double dsdy, double dtdy) noexcept {
  const double ax = dsdx * s.lod_width, bx = dtdx * s.lod_height;
  const double ay = dsdy * s.lod_width, by = dtdy * s.lod_height;
  const double px = ax * ax + bx * bx, py = ay * ay + by * by;
  const double rho2 = px > py ? px : py;
  if (!(rho2 >= FLT_MIN)) return -1.0;
  if (rho2 > FLT_MAX) return kFarLod;
  return 0.5 * std::log2(rho2);
}

std::array<float, 4> sample_scalar(const Sampler& s, float u, float v, float lambda) noexcept {
  return sample<float>(s, u, v, lambda);
}

std::array<double, 4> sample_reference(const Sampler& s, double u, double v, double lambda) noexcept {
  return sample<double>(s, u, v, lambda);
}

std::array<double, 4> sample_cube_reference(const Sampler (&faces)[6], double rx, double ry, double rz) noexcept {
  const double ax = std::abs(rx), ay = std::abs(ry), az = std::abs(rz);
  int f;
  double sc, tc, ma;
  if (ax >= ay && ax >= az) {
    f = rx >= 0 ? 0 : 1, sc = rx >= 0 ? -rz : rz, tc = -ry, ma = ax;
  } else if (ay >= az) {
    f = ry >= 0 ? 2 : 3, sc = rx, tc = ry >= 0 ? rz : -rz, ma = ay;
  } else {
    f = rz >= 0 ? 4 : 5, sc = rz >= 0 ? rx : -rx, tc = -ry, ma = az;
  }
  return sample<double>(faces[f], 0.5 * (sc / ma + 1), 0.5 * (1 - tc / ma), 0.0);
}

}  // namespace facet::texture
