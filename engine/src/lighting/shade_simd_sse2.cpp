// The SIMD lighting kernel for sse2, built with: none (x86-64 baseline) (engine/CMakeLists.txt).
#if !defined(__SSE2__)
#error "shade_simd_sse2.cpp must be compiled with its ISA flags"
#endif

#include "lighting/shade_pbr_simd.hpp"

namespace facet::lighting::simd::sse2 {
void shade(const Params& params, const Transform* xf, const Streams& streams) {
  shade_any<xsimd::sse2>(params, xf, streams);
}
void pow_array(const PowSpec& spec, const float* x, float* out, std::size_t count) {
  pow_streams<xsimd::sse2>(spec, x, out, count);
}
bool box(const float* p, std::size_t n, float lo[3], float hi[3]) { return box_triples<xsimd::sse2>(p, n, lo, hi); }
}  // namespace facet::lighting::simd::sse2
