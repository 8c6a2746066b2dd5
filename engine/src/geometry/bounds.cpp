#include "geometry/bounds.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace facet::geometry {

// The common case (every coordinate finite) runs as a flat pass over the xyz floats with twelve
// independent min/max accumulators, which the compiler turns into packed minps/maxps (three
// registers cover four vertices). A non-finite coordinate sends the mesh to the per-vertex loop,
// which skips such vertices.
bool finite_box(const Vec3* positions, std::size_t count, Eigen::Vector3d& lo_out, Eigen::Vector3d& hi_out) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  const float* x = count == 0 ? nullptr : positions->data();
  const std::size_t n = 3 * count, blocked = n / 12 * 12;
  constexpr float kMax = 3.4028235e38f;
  float lo[12], hi[12], bad[12];
  for (int k = 0; k < 12; ++k) lo[k] = kMax, hi[k] = -kMax, bad[k] = 0.0f;
  for (std::size_t i = 0; i < blocked; i += 12) {
    for (int k = 0; k < 12; ++k) {
      const float v = x[i + k];
      lo[k] = v < lo[k] ? v : lo[k];  // NaN leaves the accumulator alone; `bad` catches it
      hi[k] = v > hi[k] ? v : hi[k];
      bad[k] = (v - v) != 0.0f || bad[k] != 0.0f ? 1.0f : 0.0f;  // Inf - Inf and NaN - NaN are NaN
    }
  }
  bool all_finite = true;
  Eigen::Vector3d lo3 = Eigen::Vector3d::Constant(HUGE_VAL), hi3 = -lo3;
  for (int k = 0; k < 12; ++k) {
    all_finite = all_finite && bad[k] == 0.0f;
    lo3[k % 3] = std::min<double>(lo3[k % 3], lo[k]);
    hi3[k % 3] = std::max<double>(hi3[k % 3], hi[k]);
  }
  for (std::size_t i = blocked; i < n; ++i) {
    const float v = x[i];
    all_finite = all_finite && std::isfinite(v);
    lo3[int(i % 3)] = std::min<double>(lo3[int(i % 3)], v);
    hi3[int(i % 3)] = std::max<double>(hi3[int(i % 3)], v);
  }
  if (!all_finite) {
    lo3 = Eigen::Vector3d::Constant(HUGE_VAL), hi3 = -lo3;
    for (const Vec3& p : std::span<const Vec3>(positions, count)) {
      if (!p.allFinite()) continue;
      lo3 = lo3.cwiseMin(p.cast<double>());
      hi3 = hi3.cwiseMax(p.cast<double>());
    }
  }
  lo_out = lo3, hi_out = hi3;
  return lo3.x() <= hi3.x();
}

}  // namespace facet::geometry
