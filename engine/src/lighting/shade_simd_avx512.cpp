// The SIMD lighting kernel for avx512, built with: -mavx512f -mavx512bw -mavx512dq -mavx512vl -mavx512cd -mfma (engine/CMakeLists.txt).
#if !defined(__AVX512F__) || !defined(__AVX512BW__) || !defined(__AVX512DQ__) || !defined(__AVX512VL__)
#error "shade_simd_avx512.cpp must be compiled with its ISA flags"
#endif

#include "lighting/shade_pbr_simd.hpp"

namespace facet::lighting::simd::avx512 {
void shade(const Params& params, const Transform* xf, const Streams& streams) {
  shade_any<xsimd::avx512bw>(params, xf, streams);
}
void pow_array(const PowSpec& spec, const float* x, float* out, std::size_t count) {
  pow_streams<xsimd::avx512bw>(spec, x, out, count);
}
// The 256-bit box: the 512-bit one ran slower on data out of cache (measured on Zen 4: an unaligned
// 64-byte load of the 12-byte triples crosses a cache line every time; see the commit).
bool box(const float* p, std::size_t n, float lo[3], float hi[3]) { return box_triples<xsimd::fma3<xsimd::avx2>>(p, n, lo, hi); }
}  // namespace facet::lighting::simd::avx512
