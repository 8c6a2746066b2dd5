// Internal: from model space to the snapped screen. Vertices are transformed to clip space once,
// classified against the frustum and the guard band, and, when inside the guard band, projected
// and snapped once, instead of once per triangle that uses them.
#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "facet/types.hpp"
#include "geometry/clip.hpp"

namespace facet::geometry {

// The raster's fixed point: screen positions snap to 1/256 pixel (24.8), within a guard band of
// +-32768 pixels (so |fixed| <= 2^23, and the rasterizers' edge products stay inside int64).
inline constexpr int kSubpixelBits = 8;
inline constexpr std::int32_t kSubpixelOne = 1 << kSubpixelBits;
inline constexpr float kGuardBandPixels = 32768.0f;

// How a pass stores depth (RenderOptions::depth). GL: window depth 0.5 z/w + 0.5 in [0, 1], far
// 1. Reversed: -near / w in [-1, 0), far (infinity) 0: float keeps the same relative precision at
// every distance (it is spent near 1 in GL's), and the LESS test and its code stay GL's. Callers
// see near / w (1 at the near plane, 0 at infinity) in a reversed pass's depth output.
struct DepthFormat {
  bool reversed = false;
  float near = 0.0f;  // reversed: the camera's near plane
  float lo() const noexcept { return reversed ? -1.0f : 0.0f; }
  float far() const noexcept { return reversed ? 0.0f : 1.0f; }  // the clear value: nothing drawn
  float output(float stored) const noexcept { return reversed ? 0.0f - stored : stored; }  // 0, not -0
};

// The pixel rectangle a pass draws into, [0, width) x [0, height), y down, and its depth format.
struct Viewport {
  int width = 0, height = 0;
  DepthFormat depth{};
  // The smallest and largest offset of a pixel's samples from its corner on either axis, in
  // 1/kSubpixelOne pixel (raster/samples.hpp): the centre for one sample.
  std::int32_t sample_lo = kSubpixelOne / 2, sample_hi = kSubpixelOne / 2;
};

// Clip planes for a viewport: |x/w| <= 2G/W - 1 keeps screen x within the guard band [-G, G]
// (likewise y).
ClipPlanes guard_band_planes(const Viewport& viewport) noexcept;

// A vertex after projection, snapped to the raster's fixed point (kSubpixelOne).
struct ScreenVertex {
  std::int32_t x, y;
  float z, inv_w;
  std::uint8_t frustum, guard;  // frustum_outcode, clip_outcode
  bool finite;                  // clip position finite
  bool projected;               // guard == 0 and the projection is finite
};

// Perspective divide and viewport: screen position snapped to fixed point, window depth, 1/w.
// False if any of them is not finite.
bool project(const ClipVertex& v, const Viewport& viewport, ScreenVertex& out) noexcept;

// Row-major 4x4 in float: the model-view-projection matrix a pass transforms positions with.
struct Mat4Rows {
  float m[16];
};
Mat4Rows to_rows(const Eigen::Matrix4d& m) noexcept;

// Clip-space positions, outcodes and (inside the guard band) screen positions of vertices
// [begin, end).
void transform_vertices(const Mat4Rows& mvp, const Vec3* positions, std::size_t begin, std::size_t end,
                        const ClipPlanes& planes, const Viewport& viewport, std::array<float, 4>* clip,
                        ScreenVertex* screen) noexcept;

}  // namespace facet::geometry
