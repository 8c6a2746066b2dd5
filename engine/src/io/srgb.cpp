#include "io/srgb.hpp"

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
}

}  // namespace facet
