#include "lighting/soa.hpp"

#include <algorithm>

#include <emmintrin.h>

namespace facet::lighting {
namespace {

// Four xyz triples (r0 = x0 y0 z0 x1, r1 = y1 z1 x2 y2, r2 = z2 x3 y3 z3) to x, y, z: five
// shuffles where the Eigen loop did twelve scalar loads and stores.
inline void transpose_in(__m128 r0, __m128 r1, __m128 r2, __m128& x, __m128& y, __m128& z) {
  const __m128 x2y2x3y3 = _mm_shuffle_ps(r1, r2, _MM_SHUFFLE(2, 1, 3, 2));
  const __m128 y0z0y1z1 = _mm_shuffle_ps(r0, r1, _MM_SHUFFLE(1, 0, 2, 1));
  x = _mm_shuffle_ps(r0, x2y2x3y3, _MM_SHUFFLE(2, 0, 3, 0));
  y = _mm_shuffle_ps(y0z0y1z1, x2y2x3y3, _MM_SHUFFLE(3, 1, 2, 0));
  z = _mm_shuffle_ps(y0z0y1z1, r2, _MM_SHUFFLE(3, 0, 3, 1));
}

// The inverse of transpose_in.
inline void transpose_out(__m128 x, __m128 y, __m128 z, __m128& r0, __m128& r1, __m128& r2) {
  const __m128 xy_lo = _mm_unpacklo_ps(x, y);                            // x0 y0 x1 y1
  const __m128 xy_hi = _mm_unpackhi_ps(x, y);                            // x2 y2 x3 y3
  const __m128 z0z1x1y1 = _mm_shuffle_ps(z, xy_lo, _MM_SHUFFLE(3, 2, 1, 0));
  const __m128 z2z3x3y3 = _mm_shuffle_ps(z, xy_hi, _MM_SHUFFLE(3, 2, 3, 2));
  r0 = _mm_shuffle_ps(xy_lo, z0z1x1y1, _MM_SHUFFLE(2, 0, 1, 0));         // x0 y0 z0 x1
  r1 = _mm_shuffle_ps(z0z1x1y1, xy_hi, _MM_SHUFFLE(1, 0, 1, 3));         // y1 z1 x2 y2
  r2 = _mm_shuffle_ps(z2z3x3y3, z2z3x3y3, _MM_SHUFFLE(1, 3, 2, 0));      // z2 x3 y3 z3
}

}  // namespace

void deinterleave3(const Vec3* src, std::size_t n, float scale, float* x, float* y, float* z) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  const float* s = n ? src->data() : nullptr;
  const __m128 k = _mm_set1_ps(scale);
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4, s += 12) {
    __m128 vx, vy, vz;
    transpose_in(_mm_loadu_ps(s), _mm_loadu_ps(s + 4), _mm_loadu_ps(s + 8), vx, vy, vz);
    _mm_storeu_ps(x + i, _mm_mul_ps(vx, k));
    _mm_storeu_ps(y + i, _mm_mul_ps(vy, k));
    _mm_storeu_ps(z + i, _mm_mul_ps(vz, k));
  }
  for (; i < n; ++i, s += 3) x[i] = scale * s[0], y[i] = scale * s[1], z[i] = scale * s[2];
}

void deinterleave3(const Vec3* src, const std::uint32_t* index, std::size_t n, float scale, float* x, float* y,
                   float* z) {
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& v = src[index[i]];
    x[i] = scale * v.x(), y[i] = scale * v.y(), z[i] = scale * v.z();
  }
}

void interleave3(const float* x, const float* y, const float* z, std::size_t n, const std::uint32_t* index, Vec3* dst) {
  for (std::size_t i = 0; i < n; ++i) dst[index[i]] = Vec3(x[i], y[i], z[i]);
}

void interleave3(const float* x, const float* y, const float* z, std::size_t n, Vec3* dst) {
  float* d = n ? dst->data() : nullptr;
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4, d += 12) {
    __m128 r0, r1, r2;
    transpose_out(_mm_loadu_ps(x + i), _mm_loadu_ps(y + i), _mm_loadu_ps(z + i), r0, r1, r2);
    _mm_storeu_ps(d, r0);
    _mm_storeu_ps(d + 4, r1);
    _mm_storeu_ps(d + 8, r2);
  }
  for (; i < n; ++i, d += 3) d[0] = x[i], d[1] = y[i], d[2] = z[i];
}

float farthest_squared_float(const Vec3* p, std::size_t n, const float c[3]) {
  const float* s = n ? p->data() : nullptr;
  const __m128 cx = _mm_set1_ps(c[0]), cy = _mm_set1_ps(c[1]), cz = _mm_set1_ps(c[2]);
  __m128 best = _mm_setzero_ps();
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4, s += 12) {
    __m128 vx, vy, vz;
    transpose_in(_mm_loadu_ps(s), _mm_loadu_ps(s + 4), _mm_loadu_ps(s + 8), vx, vy, vz);
    vx = _mm_sub_ps(vx, cx), vy = _mm_sub_ps(vy, cy), vz = _mm_sub_ps(vz, cz);
    const __m128 q = _mm_add_ps(_mm_add_ps(_mm_mul_ps(vx, vx), _mm_mul_ps(vy, vy)), _mm_mul_ps(vz, vz));
    best = _mm_max_ps(q, best);  // maxps returns the second operand when q is NaN
  }
  float lanes[4];
  _mm_storeu_ps(lanes, best);
  float r2 = std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
  for (; i < n; ++i, s += 3) {
    const float dx = s[0] - c[0], dy = s[1] - c[1], dz = s[2] - c[2];
    const float q = dx * dx + dy * dy + dz * dz;
    r2 = q > r2 ? q : r2;
  }
  return r2;
}

}  // namespace facet::lighting
