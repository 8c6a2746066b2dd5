#include "io/srgb.hpp"

#include <bit>
#include <cmath>

namespace facet {

void make_srgb_table(SrgbTable& table) noexcept {
  table.threshold[0] = -HUGE_VALF;
  for (int k = 1; k < 256; ++k) {
    const double encoded = (k - 0.5) / 255.0;
    const double linear = encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
    float t = static_cast<float>(linear);
    if (static_cast<double>(t) < linear) t = std::nextafter(t, HUGE_VALF);
    table.threshold[k] = t;
  }
  for (int b = 0; b < SrgbTable::kBuckets; ++b) {
    const float lo = std::bit_cast<float>((b + SrgbTable::kBucketBias) << SrgbTable::kBucketShift);
    const float hi = std::bit_cast<float>((b + 1 + SrgbTable::kBucketBias) << SrgbTable::kBucketShift);
    int base = 0;
    float inside = HUGE_VALF;
    for (int k = 1; k < 256; ++k) {
      if (table.threshold[k] <= lo) {
        ++base;
      } else if (table.threshold[k] < hi && inside == HUGE_VALF) {
        inside = table.threshold[k];  // the first inside (a test checks there is no second)
      }
    }
    // The threshold's low 16 bits (its top 16 are the bucket's), or 0x10000: no float's low bits reach it.
    const std::int32_t low = inside == HUGE_VALF ? 0x10000 : (std::bit_cast<std::int32_t>(inside) & 0xffff);
    table.bucket[b] = (base << SrgbTable::kBaseShift) | low;
  }
}

}  // namespace facet
