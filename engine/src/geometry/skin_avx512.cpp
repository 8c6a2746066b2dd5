// The morph and skinning kernels for avx512, built with: -mavx512f -mavx512bw -mavx512dq -mavx512vl -mavx512cd -mfma -ffp-contract=off (engine/CMakeLists.txt).
#if !defined(__AVX512F__)
#error "skin_avx512.cpp must be compiled with its ISA flags"
#endif
#if !defined(FACET_NO_FP_CONTRACT)
#error "skin_avx512.cpp must be compiled with -ffp-contract=off (the scalar twin's bits)"
#endif

#include "geometry/skin_simd.hpp"

namespace facet::geometry::simd::avx512 {
void morph(const MorphJob& job) { SkinKernel<xsimd::avx512bw>::morph(job); }
void skin(const SkinJob& job) { SkinKernel<xsimd::avx512bw>::skin(job); }
}  // namespace facet::geometry::simd::avx512
