// Internal: multisample patterns (RenderOptions::samples). A pixel's samples sit at fixed
// positions inside it, in the raster's fixed point (1/256 pixel) from its top-left corner on the
// y-down screen; one sample is the pixel centre. 4, 8 and 16 samples are the standard patterns of
// Direct3D and Vulkan (llvmpipe's 4x pattern is the same four points): each row and column of the
// 1/16-pixel grid holds at most one sample at 4x and 8x, so a near-horizontal or near-vertical
// edge moves coverage in steps of 1/N.
#pragma once

#include <cstdint>

#include "raster/triangle_setup.hpp"

namespace facet::raster {

inline constexpr int kMaxSamples = 16;

struct SamplePattern {
  int count = 1;
  std::int32_t x[kMaxSamples] = {kPixelCentre}, y[kMaxSamples] = {kPixelCentre};
  // The smallest and largest offset on either axis: pixels whose samples can lie in a triangle's
  // bounds (finish_setup's conservative pixel bounds).
  std::int32_t lo = kPixelCentre, hi = kPixelCentre;
};

// The pattern of `count` samples (1, 4, 8 or 16; any other count is the caller's error).
inline SamplePattern sample_pattern(int count) {
  // In 1/16 pixel from the corner (x, y), y down.
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
    p.x[s] = table[s][0] * (kSubpixelOne / 16), p.y[s] = table[s][1] * (kSubpixelOne / 16);
    for (const std::int32_t v : {p.x[s], p.y[s]}) p.lo = v < p.lo ? v : p.lo, p.hi = v > p.hi ? v : p.hi;
  }
  return p;
}

}  // namespace facet::raster
