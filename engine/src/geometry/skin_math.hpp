// Internal: the arithmetic of one skinned vertex, written once for a float (the scalar twin,
// skin.cpp) and for an xsimd batch (skin_simd.hpp), so that both make the same IEEE operations in
// the same order (every file that includes this is compiled with -ffp-contract=off). Templates in
// an unnamed namespace: each file compiled with its own ISA flags keeps its own copy.
#pragma once

#include <cmath>

#include <xsimd/xsimd.hpp>

namespace facet::geometry::skin_math {
namespace {

inline float select_lanes(bool c, float a, float b) { return c ? a : b; }
template <class B, class V>
V select_lanes(const B& c, const V& a, const V& b) {
  return xsimd::select(c, a, b);
}
inline float square_root(float v) { return std::sqrt(v); }
template <class V>
V square_root(const V& v) {
  return xsimd::sqrt(v);
}

// A blended 3x4 matrix, by rows.
template <class V>
struct Blend {
  V m[12];
  // m = w J (the first influence), then m += w J.
  void first(const V& w, const V* j) {
    for (int e = 0; e < 12; ++e) m[e] = w * j[e];
  }
  void add(const V& w, const V* j) {
    for (int e = 0; e < 12; ++e) m[e] = m[e] + w * j[e];
  }
  void point(const V& x, const V& y, const V& z, V* out) const {
    for (int r = 0; r < 3; ++r) out[r] = m[4 * r] * x + m[4 * r + 1] * y + m[4 * r + 2] * z + m[4 * r + 3];
  }
  void vector(const V& x, const V& y, const V& z, V* out) const {
    for (int r = 0; r < 3; ++r) out[r] = m[4 * r] * x + m[4 * r + 1] * y + m[4 * r + 2] * z;
  }
  // The cofactor matrix C of the 3x3 part A (A's columns a, b, c: C's columns b x c, c x a,
  // a x b), times (x, y, z), negated when det A < 0: a vector along A^-T (x, y, z).
  void cofactor(const V& x, const V& y, const V& z, V* out) const {
    const V a[3] = {m[0], m[4], m[8]}, b[3] = {m[1], m[5], m[9]}, c[3] = {m[2], m[6], m[10]};
    const V bc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
    const V ca[3] = {c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2], c[0] * a[1] - c[1] * a[0]};
    const V ab[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    const V det = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
    for (int r = 0; r < 3; ++r) {
      const V v = bc[r] * x + ca[r] * y + ab[r] * z;
      out[r] = select_lanes(det < V(0.0f), V(0.0f) - v, v);
    }
  }
};

// v / |v|, or zero for a zero (or non-finite length) vector.
template <class V>
void normalise(V* v) {
  const V len = square_root(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const auto ok = len > V(0.0f);
  for (int r = 0; r < 3; ++r) v[r] = select_lanes(ok, v[r] / len, V(0.0f));
}

}  // namespace
}  // namespace facet::geometry::skin_math
