#include "geometry/project.hpp"

#include <algorithm>
#include <cmath>

#include "raster/triangle_setup.hpp"

namespace facet::geometry {

ClipPlanes guard_band_planes(const Viewport& viewport) noexcept {
  return {2.0f * raster::kGuardBandPixels / static_cast<float>(viewport.width) - 1.0f,
          2.0f * raster::kGuardBandPixels / static_cast<float>(viewport.height) - 1.0f};
}

bool project(const ClipVertex& v, const Viewport& viewport, ScreenVertex& out) noexcept {
  const float half_w = 0.5f * static_cast<float>(viewport.width), half_h = 0.5f * static_cast<float>(viewport.height);
  const float g = raster::kGuardBandPixels;
  const float inv_w = 1.0f / v.w;
  float sx = (v.x * inv_w + 1.0f) * half_w;
  float sy = (1.0f - v.y * inv_w) * half_h;
  const float z = 0.5f * v.z * inv_w + 0.5f;
  // After near clipping w >= near for real geometry; a hostile camera can still leave w at a
  // subnormal (found by fuzz_render), so 1/w overflows. Such a piece is dropped, never cast.
  if (!std::isfinite(sx) || !std::isfinite(sy) || !std::isfinite(z) || !std::isfinite(inv_w)) return false;
  // Clipping keeps these inside the guard band up to rounding; the clamp makes overflow impossible.
  sx = std::clamp(sx, -g, g);
  sy = std::clamp(sy, -g, g);
  out.x = static_cast<std::int32_t>(std::nearbyint(sx * float(raster::kSubpixelOne)));
  out.y = static_cast<std::int32_t>(std::nearbyint(sy * float(raster::kSubpixelOne)));
  out.z = std::clamp(z, 0.0f, 1.0f);
  out.inv_w = inv_w;
  return true;
}

void transform_vertices(const Mat4Rows& mvp, const Vec3* positions, std::size_t begin, std::size_t end,
                        const ClipPlanes& planes, const Viewport& viewport, std::array<float, 4>* clip,
                        ScreenVertex* screen) noexcept {
  for (std::size_t i = begin; i != end; ++i) {
    const Vec3& p = positions[i];
    for (int row = 0; row < 4; ++row) {
      const float* m = &mvp.m[4 * row];
      clip[i][static_cast<std::size_t>(row)] = m[0] * p.x() + m[1] * p.y() + m[2] * p.z() + m[3];
    }
    const auto& c = clip[i];
    ScreenVertex& sv = screen[i];
    const ClipVertex v{c[0], c[1], c[2], c[3], {}};
    sv.finite = std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]) && std::isfinite(c[3]);
    sv.frustum = static_cast<std::uint8_t>(frustum_outcode(v));
    sv.guard = static_cast<std::uint8_t>(clip_outcode(v, planes));
    sv.projected = sv.finite && sv.guard == 0 && project(v, viewport, sv);
  }
}

}  // namespace facet::geometry
