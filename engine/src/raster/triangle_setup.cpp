#include "raster/triangle_setup.hpp"

#include <algorithm>

namespace facet::raster {

bool finish_setup(ScreenTriangle& t, int width, int height, std::int32_t sample_lo, std::int32_t sample_hi) {
  const std::int64_t min_x = std::min({t.x[0], t.x[1], t.x[2]}), max_x = std::max({t.x[0], t.x[1], t.x[2]});
  const std::int64_t min_y = std::min({t.y[0], t.y[1], t.y[2]}), max_y = std::max({t.y[0], t.y[1], t.y[2]});
  // Pixels p with a sample (p + offset, offset in [sample_lo, sample_hi]; the centre p + 1/2 for
  // one sample) in [min, max]. Floor division by 2^8 is the arithmetic shift (C++20 defines >> on
  // negative values as floor), as floor_div computes it.
  auto first = [sample_hi](std::int64_t lo) { return (lo - sample_hi + kSubpixelOne - 1) >> kSubpixelBits; };
  auto last = [sample_lo](std::int64_t hi) { return (hi - sample_lo) >> kSubpixelBits; };
  t.min_px = static_cast<int>(std::max<std::int64_t>(0, first(min_x)));
  t.max_px = static_cast<int>(std::min<std::int64_t>(width - 1, last(max_x)));
  t.min_py = static_cast<int>(std::max<std::int64_t>(0, first(min_y)));
  t.max_py = static_cast<int>(std::min<std::int64_t>(height - 1, last(max_y)));
  if (t.min_px > t.max_px || t.min_py > t.max_py) return false;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    t.bias[k] = is_top_left(std::int64_t(t.x[b]) - t.x[a], std::int64_t(t.y[b]) - t.y[a]) ? 0 : -1;
  }
  return true;
}

void compute_planes(ScreenTriangle& t, const float* z, const float* inv_w, const float (*attr)[geometry::kMaxAttributes],
                    int attribute_count) {
  constexpr double kInvOne = 1.0 / kSubpixelOne;
  const double x10 = (double(t.x[1]) - t.x[0]) * kInvOne, y10 = (double(t.y[1]) - t.y[0]) * kInvOne;
  const double x20 = (double(t.x[2]) - t.x[0]) * kInvOne, y20 = (double(t.y[2]) - t.y[0]) * kInvOne;
  const double inv_det = 1.0 / (x10 * y20 - x20 * y10);  // area2 / 2^16 != 0
  auto set = [&](Plane& p, double f0, double f1, double f2) {
    const double d1 = f1 - f0, d2 = f2 - f0;
    p.at_v0 = static_cast<float>(f0);
    p.dx = static_cast<float>((d1 * y20 - d2 * y10) * inv_det);
    p.dy = static_cast<float>((d2 * x10 - d1 * x20) * inv_det);
  };
  set(t.plane[kPlaneZ], z[0], z[1], z[2]);
  set(t.plane[kPlaneInvW], inv_w[0], inv_w[1], inv_w[2]);
  for (int a = 0; a < attribute_count; ++a) {
    set(t.plane[kPlaneAttr + a], double(attr[0][a]) * inv_w[0], double(attr[1][a]) * inv_w[1], double(attr[2][a]) * inv_w[2]);
  }
}

}  // namespace facet::raster
