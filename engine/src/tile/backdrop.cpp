#include "tile/backdrop.hpp"

#include <cmath>
#include <cstring>

#include <Eigen/LU>

#include "io/rows.hpp"
#include "lighting/image_light.hpp"
#include "lighting/setup.hpp"
#include "tile/tile_raster.hpp"

namespace facet::tile {

Backdrop make_backdrop(const lighting::ImageLight& light, const EnvironmentLight& env, const Eigen::Matrix4d& view,
                       const Eigen::Matrix4d& projection, int width, int height) {
  Backdrop b;
  b.light = &light;
  b.intensity = env.intensity;
  // The eye-space ray through normalised device coordinates (x, y): from the near plane's point to
  // the far plane's, affine in (x, y) for perspective and orthographic projections alike.
  const Eigen::Matrix4d inverse = projection.inverse();
  auto ray = [&](double x, double y) {
    const Eigen::Vector4d n = inverse * Eigen::Vector4d(x, y, -1.0, 1.0), f = inverse * Eigen::Vector4d(x, y, 1.0, 1.0);
    return Eigen::Vector3d(f.head<3>() / f.w() - n.head<3>() / n.w());
  };
  const Eigen::Vector3d centre = ray(0.0, 0.0);
  Eigen::Matrix3d eye;
  eye.col(0) = ray(1.0, 0.0) - centre, eye.col(1) = ray(0.0, 1.0) - centre, eye.col(2) = centre;
  // Pixel centres -> device coordinates: x to the right, y up, row 0 at the top.
  Eigen::Matrix3d device;
  device << 2.0 / width, 0.0, -1.0, 0.0, -2.0 / height, 1.0, 0.0, 0.0, 1.0;
  const Eigen::Matrix3d m = lighting::environment_frame(env, view) * eye * device;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) b.ray[3 * r + c] = m(r, c);
  return b;
}

void backdrop_pixel(const Backdrop& b, int x, int y, float rgba[4]) {
  const double px = x + 0.5, py = y + 0.5;
  const double* m = b.ray;
  const double dx = m[0] * px + m[1] * py + m[2], dy = m[3] * px + m[4] * py + m[5], dz = m[6] * px + m[7] * py + m[8];
  const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double inv = len > 0.0 ? 1.0 / len : 0.0;
  const lighting::V3<float> c =
      len > 0.0 ? b.light->picture(float(dx * inv), float(dy * inv), float(dz * inv)) : b.light->picture(0.0f, 0.0f, -1.0f);
  rgba[0] = b.intensity * c.x;
  rgba[1] = b.intensity * c.y;
  rgba[2] = b.intensity * c.z;
  rgba[3] = 1.0f;
}

void fill_backdrop(const Backdrop& b, const TileRect& rect, TileBuffers& tile, float far) {
  for (int y = rect.y0; y < rect.y1; ++y) {
    for (int x = rect.x0; x < rect.x1; ++x) {
      float rgba[4];
      backdrop_pixel(b, x, y, rgba);
      for (int s = 0; s < tile.samples; ++s) {
        const std::size_t p = tile.index(x - rect.x0, y - rect.y0) + static_cast<std::size_t>(s) * tile.sample_stride();
        for (int c = 0; c < 4; ++c) tile.plane(c)[p] = rgba[c];
        tile.plane(4)[p] = far;
      }
    }
  }
}

void resolve_backdrop_tile(const Backdrop& b, const SrgbTable* srgb, const TileRect& rect, const ImageView& color,
                           const DepthView* depth, float far_depth) {
  const std::size_t bpp = bytes_per_pixel(color.format);
  for (int y = rect.y0; y < rect.y1; ++y) {
    std::uint8_t* dst = io::row_bytes(color, y) + static_cast<std::size_t>(rect.x0) * bpp;
    for (int x = rect.x0; x < rect.x1; ++x) {
      float rgba[4];
      backdrop_pixel(b, x, y, rgba);
      store_pixel(rgba, color.format, srgb, dst + static_cast<std::size_t>(x - rect.x0) * bpp);
    }
    if (depth) {
      std::uint8_t* d = io::row_bytes(*depth, y) + static_cast<std::size_t>(rect.x0) * sizeof(float);
      for (int x = rect.x0; x < rect.x1; ++x) std::memcpy(d + sizeof(float) * static_cast<std::size_t>(x - rect.x0), &far_depth, sizeof(float));
    }
  }
}

}  // namespace facet::tile
