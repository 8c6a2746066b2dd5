// The morph and skinning kernels for avx2, built with: -mavx2 -mfma -ffp-contract=off (engine/CMakeLists.txt).
#if !defined(__AVX2__) || !defined(__FMA__)
#error "skin_avx2.cpp must be compiled with its ISA flags"
#endif
#if !defined(FACET_NO_FP_CONTRACT)
#error "skin_avx2.cpp must be compiled with -ffp-contract=off (the scalar twin's bits)"
#endif

#include "geometry/skin_simd.hpp"

namespace facet::geometry::simd::avx2 {
void morph(const MorphJob& job) { SkinKernel<xsimd::fma3<xsimd::avx2>>::morph(job); }
void skin(const SkinJob& job) { SkinKernel<xsimd::fma3<xsimd::avx2>>::skin(job); }
}  // namespace facet::geometry::simd::avx2
