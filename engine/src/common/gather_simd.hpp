// Internal: 32-bit gathers for the per-ISA kernels, a template on the xsimd architecture (xsimd
// 8.1 has none for avx512bw and emulates them badly elsewhere): the hardware's on avx2 and avx512,
// element loads on sse2. Included only by the per-ISA files; everything is a template in an
// unnamed namespace (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
#pragma once

#include <cstdint>
#include <type_traits>

#include <immintrin.h>

#include <xsimd/xsimd.hpp>

namespace facet::simd_util {
namespace {

// out[l] = base[index[l]] for every lane l.
template <class Arch>
xsimd::batch<std::int32_t, Arch> gather32(const std::int32_t* base, const xsimd::batch<std::int32_t, Arch>& index) {
  using I = xsimd::batch<std::int32_t, Arch>;
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    // The masked form: GCC 12 warns on the plain intrinsic's undefined pass-through operand.
    return I(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), __mmask16(0xffff), index, base, 4));
  } else if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
    return I(_mm256_i32gather_epi32(base, index, 4));
  } else {
    constexpr int W = static_cast<int>(I::size);
    alignas(64) std::int32_t at[W], out[W];
    index.store_aligned(at);
    for (int l = 0; l < W; ++l) out[l] = base[at[l]];
    return I::load_aligned(out);
  }
}

}  // namespace
}  // namespace facet::simd_util
