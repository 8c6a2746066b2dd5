// Internal: linear -> sRGB encoding of 8-bit output (IEC 61966-2-1), exact: each channel becomes
// the correctly rounded 8-bit value of the sRGB transfer function of the float it holds, as if
// encode(x) were computed exactly and then rounded half up like to_unorm8.
//
// How: threshold[k] (k = 1..255) is the least float x with encode(x) * 255 >= k - 1/2, computed
// once in double from the inverse function (and moved up one ulp when the float rounding fell
// below it); the 8-bit value of x is the number of thresholds <= x, found by an 8-step binary
// search. NaN gives 0, values above 1 give 255. Plain data: the SIMD resolve reads the table.
#pragma once

#include <cstdint>

namespace facet {

struct SrgbTable {
  float threshold[256];  // threshold[0] unused
};

void make_srgb_table(SrgbTable& table) noexcept;

// The scalar resolve's encoder (the SIMD kernels have their own copy of the search).
inline std::uint8_t srgb_unorm8(const float* threshold, float v) noexcept {
  int k = 0;
  for (int step = 128; step >= 1; step >>= 1) {
    if (v >= threshold[k + step]) k += step;
  }
  return static_cast<std::uint8_t>(k);
}

}  // namespace facet
