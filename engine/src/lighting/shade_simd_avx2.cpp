// The SIMD lighting kernel for avx2, built with: -mavx2 -mfma (engine/CMakeLists.txt).
#if !defined(__AVX2__) || !defined(__FMA__)
#error "shade_simd_avx2.cpp must be compiled with its ISA flags"
#endif

#include "lighting/shade_pbr_simd.hpp"

namespace facet::lighting::simd::avx2 {
void shade(const Params& params, const Transform* xf, const Streams& streams) {
  shade_any<xsimd::fma3<xsimd::avx2>>(params, xf, streams);
}
void pow_array(const PowSpec& spec, const float* x, float* out, std::size_t count) {
  pow_streams<xsimd::fma3<xsimd::avx2>>(spec, x, out, count);
}
bool box(const float* p, std::size_t n, float lo[3], float hi[3]) { return box_triples<xsimd::fma3<xsimd::avx2>>(p, n, lo, hi); }
}  // namespace facet::lighting::simd::avx2
