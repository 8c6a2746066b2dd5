#include "raster/samples.hpp"

namespace facet::raster {

SamplePattern sample_pattern(int count) {
  // In 1/16 pixel from the lower-left corner, y up (GL's window coordinates).
  static constexpr std::int8_t k4[4][2] = {{6, 2}, {14, 6}, {2, 10}, {10, 14}};
  static constexpr std::int8_t k8[8][2] = {{9, 5}, {7, 11}, {13, 9}, {5, 3}, {3, 13}, {1, 7}, {11, 15}, {15, 1}};
  static constexpr std::int8_t k16[16][2] = {{9, 9},  {7, 5},  {5, 10}, {12, 7}, {3, 6},  {10, 13}, {13, 11}, {11, 3},
                                             {6, 14}, {8, 1},  {4, 2},  {2, 12}, {0, 8},  {15, 4},  {14, 15}, {1, 0}};
  SamplePattern p;
  const std::int8_t(*table)[2] = count == 4 ? k4 : count == 8 ? k8 : count == 16 ? k16 : nullptr;
  if (!table) return p;
  p.count = count;
  p.lo = kSubpixelOne, p.hi = 0;
  for (int s = 0; s < count; ++s) {
    p.x[s] = table[s][0] * (kSubpixelOne / 16), p.y[s] = (16 - table[s][1]) * (kSubpixelOne / 16);
    for (const std::int32_t v : {p.x[s], p.y[s]}) p.lo = v < p.lo ? v : p.lo, p.hi = v > p.hi ? v : p.hi;
  }
  return p;
}

}  // namespace facet::raster
