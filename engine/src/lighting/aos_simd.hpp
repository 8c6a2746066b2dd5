// Internal: xyz triples (a mesh's positions, normals and colours as they lie in memory) to and from
// one batch per coordinate, in registers, for the lighting kernel that reads the mesh's arrays
// itself (shade_simd.hpp). Included only by the per-ISA files shade_simd_<isa>.cpp; everything is a
// template on the batch type or in an unnamed namespace, so no inline code is shared between ISA
// files (the linker would merge copies compiled with different flags).
//
// A batch of W float lanes reads 3 W consecutive floats:
//   - sse2 (W = 4): three loads and five shuffles;
//   - avx2 (W = 8): the same shuffles on both 128-bit halves, vertices 0-3 in the low half and 4-7
//     in the high one (three loads, three inserts);
//   - avx512 (W = 16): three loads and two two-source permutes per coordinate.
// Double lanes (the exact tier) take the float transpose of half the width, widened exactly (and
// rounded to nearest on the way out, as a float store of a double rounds); sse2's two through a
// small buffer.
// Every path moves the floats unchanged, so a kernel reading triples computes on exactly the
// values it read from structure-of-arrays copies (the same bytes out).
#pragma once

#include <cstddef>
#include <type_traits>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

namespace facet::lighting::simd {
namespace {  // per ISA file: see the top of this file

// r0 = x0 y0 z0 x1, r1 = y1 z1 x2 y2, r2 = z2 x3 y3 z3 (per 128-bit half) to x, y, z.
template <class R, class Shuffle>
inline void xyz_transpose_in(R r0, R r1, R r2, R& x, R& y, R& z, Shuffle shuffle) {
  const R x2y2x3y3 = shuffle.template apply<_MM_SHUFFLE(2, 1, 3, 2)>(r1, r2);
  const R y0z0y1z1 = shuffle.template apply<_MM_SHUFFLE(1, 0, 2, 1)>(r0, r1);
  x = shuffle.template apply<_MM_SHUFFLE(2, 0, 3, 0)>(r0, x2y2x3y3);
  y = shuffle.template apply<_MM_SHUFFLE(3, 1, 2, 0)>(y0z0y1z1, x2y2x3y3);
  z = shuffle.template apply<_MM_SHUFFLE(3, 0, 3, 1)>(y0z0y1z1, r2);
}

struct Shuffle128 {
  template <int M>
  static __m128 apply(__m128 a, __m128 b) { return _mm_shuffle_ps(a, b, M); }
};

// Only in the avx2 and avx512 files' instantiations (the caller's ISA flags provide the intrinsic).
struct Shuffle256 {
  template <int M>
  static __m256 apply(__m256 a, __m256 b) { return _mm256_shuffle_ps(a, b, M); }
};

// The permute indices of avx512's triples (element e of the 48 floats is coordinate e % 3 of
// vertex e / 3): a first permute over the first two registers, a second one over its result and
// the third register.
struct TripleIndex512 {
  alignas(64) int in_ab[3][16], in_c[3][16], out_ab[3][16], out_c[3][16];
};

inline constexpr TripleIndex512 make_triple_index512() {
  TripleIndex512 t{};
  for (int c = 0; c < 3; ++c) {
    for (int v = 0; v < 16; ++v) {
      const int e = 3 * v + c;  // vertex v's coordinate c among the 48 floats
      t.in_ab[c][v] = e < 32 ? e : 0;
      t.in_c[c][v] = e < 32 ? v : 16 + (e - 32);
    }
    // Output register c holds elements 16 c .. 16 c + 15: element e is coordinate e % 3 (x, y
    // or z batch) of vertex e / 3. The first permute picks from x (index v) and y (16 + v); the
    // second keeps those lanes (index l) or takes z (16 + v).
    for (int l = 0; l < 16; ++l) {
      const int e = 16 * c + l, v = e / 3, k = e % 3;
      t.out_ab[c][l] = k == 0 ? v : k == 1 ? 16 + v : 0;
      t.out_c[c][l] = k == 2 ? 16 + v : l;
    }
  }
  return t;
}

inline constexpr TripleIndex512 kTripleIndex512 = make_triple_index512();

// Four triples (12 floats) to and from x, y, z.
inline void load_xyz4(const float* src, __m128& x, __m128& y, __m128& z) {
  xyz_transpose_in(_mm_loadu_ps(src), _mm_loadu_ps(src + 4), _mm_loadu_ps(src + 8), x, y, z, Shuffle128{});
}

// The inverse of xyz_transpose_in, per 128-bit half.
template <class R, class Shuffle, class Lo, class Hi>
inline void xyz_transpose_out(R x, R y, R z, R& r0, R& r1, R& r2, Shuffle shuffle, Lo unpacklo, Hi unpackhi) {
  const R xy_lo = unpacklo(x, y);  // x0 y0 x1 y1
  const R xy_hi = unpackhi(x, y);  // x2 y2 x3 y3
  const R z0z1x1y1 = shuffle.template apply<_MM_SHUFFLE(3, 2, 1, 0)>(z, xy_lo);
  const R z2z3x3y3 = shuffle.template apply<_MM_SHUFFLE(3, 2, 3, 2)>(z, xy_hi);
  r0 = shuffle.template apply<_MM_SHUFFLE(2, 0, 1, 0)>(xy_lo, z0z1x1y1);
  r1 = shuffle.template apply<_MM_SHUFFLE(1, 0, 1, 3)>(z0z1x1y1, xy_hi);
  r2 = shuffle.template apply<_MM_SHUFFLE(1, 3, 2, 0)>(z2z3x3y3, z2z3x3y3);
}

inline void store_xyz4(__m128 x, __m128 y, __m128 z, float* dst) {
  __m128 r0, r1, r2;
  xyz_transpose_out(x, y, z, r0, r1, r2, Shuffle128{}, [](__m128 a, __m128 b) { return _mm_unpacklo_ps(a, b); },
                    [](__m128 a, __m128 b) { return _mm_unpackhi_ps(a, b); });
  _mm_storeu_ps(dst, r0);
  _mm_storeu_ps(dst + 4, r1);
  _mm_storeu_ps(dst + 8, r2);
}

// Eight triples: vertices 0-3 in the low 128-bit half, 4-7 in the high one. Templates on the
// caller's architecture, so that only the avx2 and avx512 files compile them.
template <class A>
inline void load_xyz8(const float* src, __m256& x, __m256& y, __m256& z) {
  auto pair = [&](int at) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(src + at)), _mm_loadu_ps(src + 12 + at), 1);
  };
  xyz_transpose_in(pair(0), pair(4), pair(8), x, y, z, Shuffle256{});
}

template <class A>
inline void store_xyz8(__m256 x, __m256 y, __m256 z, float* dst) {
  __m256 r0, r1, r2;
  xyz_transpose_out(x, y, z, r0, r1, r2, Shuffle256{}, [](__m256 a, __m256 b) { return _mm256_unpacklo_ps(a, b); },
                    [](__m256 a, __m256 b) { return _mm256_unpackhi_ps(a, b); });
  _mm_storeu_ps(dst, _mm256_castps256_ps128(r0));
  _mm_storeu_ps(dst + 4, _mm256_castps256_ps128(r1));
  _mm_storeu_ps(dst + 8, _mm256_castps256_ps128(r2));
  _mm_storeu_ps(dst + 12, _mm256_extractf128_ps(r0, 1));
  _mm_storeu_ps(dst + 16, _mm256_extractf128_ps(r1, 1));
  _mm_storeu_ps(dst + 20, _mm256_extractf128_ps(r2, 1));
}

// Reads B::size triples from src (3 B::size floats) into x, y, z.
template <class B>
inline void load_xyz(const float* src, B& x, B& y, B& z) {
  using A = typename B::arch_type;
  using T = typename B::value_type;
  constexpr std::size_t W = B::size;
  if constexpr (std::is_same_v<T, float> && std::is_base_of_v<xsimd::avx512f, A>) {
    const __m512 a = _mm512_loadu_ps(src), b = _mm512_loadu_ps(src + 16), c = _mm512_loadu_ps(src + 32);
    const TripleIndex512& t = kTripleIndex512;
    B* out[3] = {&x, &y, &z};
    for (int k = 0; k < 3; ++k) {
      const __m512 ab = _mm512_permutex2var_ps(a, _mm512_load_si512(t.in_ab[k]), b);
      *out[k] = B(_mm512_permutex2var_ps(ab, _mm512_load_si512(t.in_c[k]), c));
    }
  } else if constexpr (std::is_same_v<T, float> && std::is_base_of_v<xsimd::avx, A>) {
    __m256 vx, vy, vz;
    load_xyz8<A>(src, vx, vy, vz);
    x = B(vx), y = B(vy), z = B(vz);
  } else if constexpr (std::is_same_v<T, float> && W == 4) {
    __m128 vx, vy, vz;
    load_xyz4(src, vx, vy, vz);
    x = B(vx), y = B(vy), z = B(vz);
  } else if constexpr (std::is_same_v<T, double> && std::is_base_of_v<xsimd::avx512f, A>) {
    __m256 fx, fy, fz;  // eight floats, widened exactly
    load_xyz8<A>(src, fx, fy, fz);
    x = B(_mm512_cvtps_pd(fx)), y = B(_mm512_cvtps_pd(fy)), z = B(_mm512_cvtps_pd(fz));
  } else if constexpr (std::is_same_v<T, double> && std::is_base_of_v<xsimd::avx, A>) {
    __m128 fx, fy, fz;  // four floats, widened exactly
    load_xyz4(src, fx, fy, fz);
    x = B(_mm256_cvtps_pd(fx)), y = B(_mm256_cvtps_pd(fy)), z = B(_mm256_cvtps_pd(fz));
  } else {
    alignas(64) T bx[W], by[W], bz[W];
    for (std::size_t l = 0; l < W; ++l) bx[l] = src[3 * l], by[l] = src[3 * l + 1], bz[l] = src[3 * l + 2];
    x = B::load_aligned(bx), y = B::load_aligned(by), z = B::load_aligned(bz);
  }
}

// Writes x, y, z as B::size triples to dst (3 B::size floats).
template <class B>
inline void store_xyz(const B& x, const B& y, const B& z, float* dst) {
  using A = typename B::arch_type;
  using T = typename B::value_type;
  constexpr std::size_t W = B::size;
  if constexpr (std::is_same_v<T, float> && std::is_base_of_v<xsimd::avx512f, A>) {
    const TripleIndex512& t = kTripleIndex512;
    for (int k = 0; k < 3; ++k) {
      const __m512 xy = _mm512_permutex2var_ps(x, _mm512_load_si512(t.out_ab[k]), y);
      _mm512_storeu_ps(dst + 16 * k, _mm512_permutex2var_ps(xy, _mm512_load_si512(t.out_c[k]), z));
    }
  } else if constexpr (std::is_same_v<T, float> && std::is_base_of_v<xsimd::avx, A>) {
    store_xyz8<A>(x, y, z, dst);
  } else if constexpr (std::is_same_v<T, float> && W == 4) {
    store_xyz4(x, y, z, dst);
  } else if constexpr (std::is_same_v<T, double> && std::is_base_of_v<xsimd::avx512f, A>) {
    // Rounded to nearest, as a float store of a double rounds.
    store_xyz8<A>(_mm512_cvtpd_ps(x), _mm512_cvtpd_ps(y), _mm512_cvtpd_ps(z), dst);
  } else if constexpr (std::is_same_v<T, double> && std::is_base_of_v<xsimd::avx, A>) {
    store_xyz4(_mm256_cvtpd_ps(x), _mm256_cvtpd_ps(y), _mm256_cvtpd_ps(z), dst);
  } else {
    alignas(64) T bx[W], by[W], bz[W];
    x.store_aligned(bx), y.store_aligned(by), z.store_aligned(bz);
    for (std::size_t l = 0; l < W; ++l) {
      dst[3 * l] = static_cast<float>(bx[l]), dst[3 * l + 1] = static_cast<float>(by[l]), dst[3 * l + 2] = static_cast<float>(bz[l]);
    }
  }
}

}  // namespace
}  // namespace facet::lighting::simd
