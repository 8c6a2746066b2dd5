// Internal: linear -> sRGB encoding of 8-bit output (IEC 61966-2-1), exact: each channel becomes
// the correctly rounded 8-bit value of the sRGB transfer function of the float it holds, as if
// encode(x) were computed exactly and then rounded half up like to_unorm8.
//
// How: threshold[k] (k = 1..255) is the least float x with encode(x) * 255 >= k - 1/2, computed
// once in double from the inverse function (and moved up one ulp when the float rounding fell
// below it); the 8-bit value of x is the number of thresholds <= x, found by an 8-step binary
// search. NaN gives 0, values above 1 give 255. Plain data: the SIMD resolve reads the table.
//
// The SIMD resolve counts the same thresholds without a search: a float x in [2^-13, 1) falls in
// bucket (bits(x) >> 16) - kBucketBias, its exponent and top 7 mantissa bits, and no bucket holds
// more than one threshold (buckets are narrower than the gaps between thresholds: 2^-8 wide below
// 1, where the gaps are 0.0089 wide, and narrower still where the gaps narrow; checked by a test),
// so the byte is the bucket's base count plus (x >= the threshold inside it). A bucket's floats share
// their top 16 bits, so the comparison needs only the low 16: one 32-bit entry holds both,
// base << 17 | the threshold's low 16 bits (0x10000 when the bucket holds none), and the encoders
// read one entry per channel (one gather). Below 2^-13 every x gives 0 (threshold[1] is 1.5e-4),
// from 1 on 255.
#pragma once

#include <bit>
#include <cstdint>

namespace facet {

struct SrgbTable {
  float threshold[256];  // threshold[0] unused
  static constexpr int kBucketShift = 16;
  static constexpr std::int32_t kBucketBias = (127 - 13) << 7;  // bucket 0 starts at 2^-13
  static constexpr int kBuckets = 13 << 7;                      // the last ends at 1
  static constexpr int kBaseShift = 17;
  static constexpr std::int32_t kLowMask = 0x1ffff;  // the threshold's low bits, or 0x10000 (none)
  std::int32_t bucket[kBuckets];
};

void make_srgb_table(SrgbTable& table) noexcept;

// The definition: the number of thresholds <= v, by binary search (what the tests hold the
// encoders below to).
inline std::uint8_t srgb_unorm8_search(const float* threshold, float v) noexcept {
  int k = 0;
  for (int step = 128; step >= 1; step >>= 1) {
    if (v >= threshold[k + step]) k += step;
  }
  return static_cast<std::uint8_t>(k);
}

// The scalar encoder (store_pixel, the display pass): the same count through the buckets, one
// load and no search (the SIMD resolve has its own copy).
inline std::uint8_t srgb_unorm8(const SrgbTable& t, float v) noexcept {
  if (!(v >= 0x1p-13f)) return 0;  // NaN too
  if (v >= 1.0f) return 255;
  const std::int32_t bits = std::bit_cast<std::int32_t>(v);
  const std::int32_t e = t.bucket[(bits >> SrgbTable::kBucketShift) - SrgbTable::kBucketBias];
  return static_cast<std::uint8_t>((e >> SrgbTable::kBaseShift) + ((bits & 0xffff) >= (e & SrgbTable::kLowMask) ? 1 : 0));
}

}  // namespace facet
