// Internal: diffuse light from an environment by order-2 spherical harmonics (Ramamoorthi and
// Hanrahan, "An Efficient Representation for Irradiance Environment Maps", 2001), in double: the
// reference the image-based lighting's irradiance will be measured against.
//
// Radiance L(w) is projected onto the nine real harmonics Y_lm (l <= 2); the irradiance at a
// normal n, E(n) = integral of L(w) max(0, n.w) dw, is then
//   E(n) = sum over l, m of A_l L_lm Y_lm(n),   A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4,
// exact for an environment without harmonics above l = 2 (the clamped cosine's own are small
// there: about 3 % of the irradiance on average for natural light, by the paper's measure).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "lighting/shade.hpp"

namespace facet::lighting::sh9 {

using Coefficients = std::array<V3<double>, 9>;

// Y_00, Y_1-1, Y_10, Y_11, Y_2-2, Y_2-1, Y_20, Y_21, Y_22 at the unit direction d.
inline std::array<double, 9> basis(const V3<double>& d) {
  const double x = d.x, y = d.y, z = d.z;
  return {0.28209479177387814,
          0.4886025119029199 * y,
          0.4886025119029199 * z,
          0.4886025119029199 * x,
          1.0925484305920792 * x * y,
          1.0925484305920792 * y * z,
          0.31539156525252005 * (3.0 * z * z - 1.0),
          1.0925484305920792 * x * z,
          0.5462742152960396 * (x * x - y * y)};
}

// Adds radiance L arriving from the unit direction d over the solid angle `weight`.
inline void accumulate(Coefficients& c, const V3<double>& d, const V3<double>& radiance, double weight) {
  const std::array<double, 9> y = basis(d);
  for (int k = 0; k < 9; ++k) {
    c[k].x += radiance.x * y[k] * weight;
    c[k].y += radiance.y * y[k] * weight;
    c[k].z += radiance.z * y[k] * weight;
  }
}

// Projects radiance(d) by a midpoint grid of n_theta x n_phi cells over the sphere, each weighed
// by its exact solid angle.
template <class Radiance>
Coefficients project(const Radiance& radiance, int n_theta, int n_phi) {
  Coefficients c{};
  const double pi = std::numbers::pi;
  for (int i = 0; i < n_theta; ++i) {
    const double t0 = pi * i / n_theta, t1 = pi * (i + 1) / n_theta, theta = 0.5 * (t0 + t1);
    const double cell = (std::cos(t0) - std::cos(t1)) * (2.0 * pi / n_phi);
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * pi * (j + 0.5) / n_phi;
      const V3<double> d{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      accumulate(c, d, radiance(d), cell);
    }
  }
  return c;
}

// E(n) for a unit normal n.
inline V3<double> irradiance(const Coefficients& c, const V3<double>& n) {
  const double pi = std::numbers::pi;
  const double a[9] = {pi, 2.0 * pi / 3.0, 2.0 * pi / 3.0, 2.0 * pi / 3.0, pi / 4.0, pi / 4.0, pi / 4.0, pi / 4.0, pi / 4.0};
  const std::array<double, 9> y = basis(n);
  V3<double> e{0.0, 0.0, 0.0};
  for (int k = 0; k < 9; ++k) {
    e.x += a[k] * c[k].x * y[k];
    e.y += a[k] * c[k].y * y[k];
    e.z += a[k] * c[k].z * y[k];
  }
  return e;
}

// The direction at the centre of texel (column c, row r) of a width x height equirectangular
// picture stored top row first, in facet's convention (facet::equirect_coordinates: u = 1/2 +
// atan2(d.x, -d.z) / 2 pi, v = 1/2 + asin(d.y) / pi, v = 1 the top row): the picture's centre
// looks along -Z, its top row is +Y.
inline V3<double> equirect_direction(int c, int r, int width, int height) {
  const double pi = std::numbers::pi;
  const double u = (c + 0.5) / width, v = 1.0 - (r + 0.5) / height;
  const double elevation = (v - 0.5) * pi, azimuth = (u - 0.5) * 2.0 * pi;
  return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), -std::cos(elevation) * std::cos(azimuth)};
}

// Projects a float RGB equirectangular picture (top row first, 3 floats a texel), each texel
// weighed by the exact solid angle of its cell.
inline Coefficients project_equirect(const float* rgb, int width, int height) {
  Coefficients c{};
  const double pi = std::numbers::pi;
  for (int r = 0; r < height; ++r) {
    const double top = pi / 2.0 - pi * r / height, bottom = pi / 2.0 - pi * (r + 1) / height;
    const double cell = (std::sin(top) - std::sin(bottom)) * (2.0 * pi / width);
    for (int col = 0; col < width; ++col) {
      const float* t = rgb + 3 * (static_cast<std::size_t>(r) * width + col);
      accumulate(c, equirect_direction(col, r, width, height), V3<double>{t[0], t[1], t[2]}, cell);
    }
  }
  return c;
}

}  // namespace facet::lighting::sh9
