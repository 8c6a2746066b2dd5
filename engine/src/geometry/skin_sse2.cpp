// The morph and skinning kernels for sse2, built with: -ffp-contract=off (engine/CMakeLists.txt).
#if !defined(__SSE2__)
#error "skin_sse2.cpp must be compiled with its ISA flags"
#endif
#if !defined(FACET_NO_FP_CONTRACT)
#error "skin_sse2.cpp must be compiled with -ffp-contract=off (the scalar twin's bits)"
#endif

#include "geometry/skin_simd.hpp"

namespace facet::geometry::simd::sse2 {
void morph(const MorphJob& job) { SkinKernel<xsimd::sse2>::morph(job); }
void skin(const SkinJob& job) { SkinKernel<xsimd::sse2>::skin(job); }
}  // namespace facet::geometry::simd::sse2
