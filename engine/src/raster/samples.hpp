// Internal: multisample patterns (RenderOptions::samples). A pixel's samples sit at fixed
// positions inside it, in the raster's fixed point (1/256 pixel) from its top-left corner on the
// y-down screen; one sample is the pixel centre. 4, 8 and 16 samples are the standard positions
// Mesa's drivers use (llvmpipe's lp_sample_pos_4x for 4): the tables below are those numbers, in
// 1/16 pixel, measured as GL measures them, from the pixel's lower-left corner in a y-up window,
// so facet's y-down offset is 16 - y. (Direct3D and Vulkan give the same numbers from the
// upper-left corner: their pattern is this one mirrored top to bottom; measured against llvmpipe's
// 4x images, the mirrored pattern left 0.5-1.3 % of the pixels more than 8 steps apart at edges,
// this one none.) Each row and column of the 1/16-pixel grid holds at most one sample at 4x and
// 8x, so a near-horizontal or near-vertical edge moves coverage in steps of 1/N.
#pragma once

#include <cstdint>

#include "raster/triangle_setup.hpp"

namespace facet::raster {

inline constexpr int kMaxSamples = 16;

struct SamplePattern {
  int count = 1;
  std::int32_t x[kMaxSamples] = {kPixelCentre}, y[kMaxSamples] = {kPixelCentre};
  // The smallest and largest offset on either axis (0..kSubpixelOne; 16 samples reach both
  // edges): pixels whose samples can lie in a triangle's bounds (finish_setup's pixel bounds).
  std::int32_t lo = kPixelCentre, hi = kPixelCentre;
};

// The pattern of `count` samples (1, 4, 8 or 16; any other count: one sample). Defined out of
// line: the per-ISA files include this header, and no inline function may cross them.
SamplePattern sample_pattern(int count);

}  // namespace facet::raster
