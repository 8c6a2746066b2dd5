#include "geometry/project.hpp"

#include <algorithm>
#include <cmath>

#include <immintrin.h>


namespace facet::geometry {

Mat4Rows to_rows(const Eigen::Matrix4d& m) noexcept {
  Mat4Rows r{};
  for (int i = 0; i < 16; ++i) r.m[i] = static_cast<float>(m(i / 4, i % 4));
  return r;
}

ClipPlanes guard_band_planes(const Viewport& viewport) noexcept {
  return {2.0f * kGuardBandPixels / static_cast<float>(viewport.width) - 1.0f,
          2.0f * kGuardBandPixels / static_cast<float>(viewport.height) - 1.0f};
}

namespace {

// x rounded to the nearest integer in the current rounding mode (ties to even by default), as
// std::nearbyint then a cast: cvtss2si rounds by MXCSR as nearbyintf does, without a libm call.
// |x| <= 2^23 here (clamped to the guard band), well inside int32.
std::int32_t round_to_int(float x) noexcept { return _mm_cvtss_si32(_mm_set_ss(x)); }

bool project_xyzw(float x, float y, float zc, float w, const Viewport& viewport, ScreenVertex& out) noexcept {
  const float half_w = 0.5f * static_cast<float>(viewport.width), half_h = 0.5f * static_cast<float>(viewport.height);
  const float g = kGuardBandPixels;
  const float inv_w = 1.0f / w;
  float sx = (x * inv_w + 1.0f) * half_w;
  float sy = (1.0f - y * inv_w) * half_h;
  const float z = 0.5f * zc * inv_w + 0.5f;
  // After near clipping w >= near for real geometry; a hostile camera can still leave w at a
  // subnormal (found by fuzz_render), so 1/w overflows. Such a piece is dropped, never cast.
  if (!std::isfinite(sx) || !std::isfinite(sy) || !std::isfinite(z) || !std::isfinite(inv_w)) return false;
  // Clipping keeps these inside the guard band up to rounding; the clamp makes overflow impossible.
  sx = std::clamp(sx, -g, g);
  sy = std::clamp(sy, -g, g);
  out.x = round_to_int(sx * float(kSubpixelOne));
  out.y = round_to_int(sy * float(kSubpixelOne));
  out.z = std::clamp(viewport.depth.reversed ? -viewport.depth.near * inv_w : z, viewport.depth.lo(), viewport.depth.far());
  out.inv_w = inv_w;
  return true;
}

}  // namespace

bool project(const ClipVertex& v, const Viewport& viewport, ScreenVertex& out) noexcept {
  return project_xyzw(v.x, v.y, v.z, v.w, viewport, out);
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
    sv.finite = std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]) && std::isfinite(c[3]);
    sv.frustum = static_cast<std::uint8_t>(frustum_outcode(c[0], c[1], c[2], c[3]));
    sv.guard = static_cast<std::uint8_t>(clip_outcode(c[0], c[1], c[2], c[3], planes));
    sv.projected = sv.finite && sv.guard == 0 && project_xyzw(c[0], c[1], c[2], c[3], viewport, sv);
  }
}

}  // namespace facet::geometry
