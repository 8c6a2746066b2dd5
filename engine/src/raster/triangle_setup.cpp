#include "raster/triangle_setup.hpp"

#include <algorithm>
#include <utility>

namespace facet::raster {

void swap_vertices_1_2(ScreenTriangle& t) {
  std::swap(t.x[1], t.x[2]);
  std::swap(t.y[1], t.y[2]);
  std::swap(t.z[1], t.z[2]);
  std::swap(t.inv_w[1], t.inv_w[2]);
  std::swap(t.attr[1], t.attr[2]);
}

bool finish_setup(ScreenTriangle& t, int width, int height) {
  const std::int64_t min_x = std::min({t.x[0], t.x[1], t.x[2]}), max_x = std::max({t.x[0], t.x[1], t.x[2]});
  const std::int64_t min_y = std::min({t.y[0], t.y[1], t.y[2]}), max_y = std::max({t.y[0], t.y[1], t.y[2]});
  // Pixels whose centre (p + 1/2) lies in [min, max].
  auto first = [](std::int64_t lo) { return floor_div(lo - kPixelCentre + kSubpixelOne - 1, kSubpixelOne); };
  auto last = [](std::int64_t hi) { return floor_div(hi - kPixelCentre, kSubpixelOne); };
  t.min_px = static_cast<int>(std::max<std::int64_t>(0, first(min_x)));
  t.max_px = static_cast<int>(std::min<std::int64_t>(width - 1, last(max_x)));
  t.min_py = static_cast<int>(std::max<std::int64_t>(0, first(min_y)));
  t.max_py = static_cast<int>(std::min<std::int64_t>(height - 1, last(max_y)));
  if (t.min_px > t.max_px || t.min_py > t.max_py) return false;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    t.bias[k] = is_top_left(std::int64_t(t.x[b]) - t.x[a], std::int64_t(t.y[b]) - t.y[a]) ? 0 : -1;
  }
  t.area2 = signed_area2(t);
  t.inv_area2 = static_cast<float>(1.0 / static_cast<double>(t.area2));
  return true;
}

}  // namespace facet::raster
