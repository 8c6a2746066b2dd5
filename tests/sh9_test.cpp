// Order-2 spherical-harmonic irradiance (lighting/sh9.hpp) against closed forms: environments
// without harmonics above l = 2 come back exactly (uniform, linear, z squared), and a sky lit from
// one side (the clamped cosine, not band-limited) within the truncation error the method is known
// for, measured against direct integration.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include <vector>

#include "facet/texture.hpp"
#include "lighting/sh9.hpp"

namespace facet::lighting {
namespace {

using V = V3<double>;
constexpr double kPiSh = std::numbers::pi;

V unit_at(double theta, double phi) {
  return {std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)};  // around +y
}

// (Exactly up to the projection grid's quadrature: 1e-4 at 256 x 512 cells.)
TEST(Sh9, BandLimitedEnvironmentsComeBackExactly) {
  const sh9::Coefficients uniform = sh9::project([](const V&) { return V{1.0, 0.5, 0.25}; }, 256, 512);
  const sh9::Coefficients linear = sh9::project([](const V& d) { return V{1.0 + d.z, 1.0 - d.x, 1.0 + 0.5 * d.y}; }, 256, 512);
  const sh9::Coefficients squared = sh9::project([](const V& d) { return V{d.z * d.z, d.x * d.x, d.x * d.y}; }, 256, 512);
  for (double theta : {0.0, 0.4, 1.1, 1.9, 2.8, kPiSh}) {
    for (double phi : {0.0, 1.0, 2.5, 4.0}) {
      const V n = unit_at(theta, phi);
      const V u = sh9::irradiance(uniform, n);
      EXPECT_NEAR(u.x, kPiSh, 1e-4);
      EXPECT_NEAR(u.z, 0.25 * kPiSh, 1e-4);
      // The irradiance of 1 + d.z is pi + (2 pi / 3) n.z (and so for the other axes).
      const V l = sh9::irradiance(linear, n);
      EXPECT_NEAR(l.x, kPiSh + 2.0 * kPiSh / 3.0 * n.z, 1e-4);
      EXPECT_NEAR(l.y, kPiSh - 2.0 * kPiSh / 3.0 * n.x, 1e-4);
      EXPECT_NEAR(l.z, kPiSh + 0.5 * 2.0 * kPiSh / 3.0 * n.y, 1e-4);
      // z^2 = 1/3 + (2/3) P2(z): irradiance pi / 3 + (pi / 6) P2(n.z), P2(m) = (3 m^2 - 1) / 2
      // (pi / 2 along z, pi / 4 across it, worked by hand).
      auto p2 = [](double m) { return 0.5 * (3.0 * m * m - 1.0); };
      const V s = sh9::irradiance(squared, n);
      EXPECT_NEAR(s.x, kPiSh / 3.0 + kPiSh / 6.0 * p2(n.z), 1e-4);
      EXPECT_NEAR(s.y, kPiSh / 3.0 + kPiSh / 6.0 * p2(n.x), 1e-4);
      // x y is a pure l = 2 harmonic: (pi / 4) x y scaled back, i.e. (pi / 4) n.x n.y.
      EXPECT_NEAR(s.z, kPiSh / 4.0 * n.x * n.y, 1e-4);
    }
  }
  const V up = sh9::irradiance(squared, V{0.0, 0.0, 1.0}), side = sh9::irradiance(squared, V{1.0, 0.0, 0.0});
  EXPECT_NEAR(up.x, kPiSh / 2.0, 1e-4);
  EXPECT_NEAR(side.x, kPiSh / 4.0, 1e-4);
}

// A sky lit from above (radiance max(0, d.y)): the exact irradiance by direct integration
// against the order-2 estimate. The clamped cosine has harmonics above l = 2 (l = 4, 6, ...),
// so the estimate is not exact; its error stays within 1.5 % of the largest irradiance (the test
// prints what it measures).
TEST(Sh9, ClampedSkyWithinTheTruncationError) {
  auto sky = [](const V& d) { const double s = d.y > 0.0 ? d.y : 0.0; return V{s, s, s}; };
  const sh9::Coefficients c = sh9::project(sky, 256, 512);
  double worst = 0.0;
  for (double theta : {0.0, 0.5, 1.0, 1.5708, 2.2, 2.8, kPiSh}) {
    const V n = unit_at(theta, 0.7);
    double exact = 0.0;
    const int nt = 400, np = 800;
    for (int i = 0; i < nt; ++i) {
      const double t0 = kPiSh * i / nt, t1 = kPiSh * (i + 1) / nt, t = 0.5 * (t0 + t1);
      const double cell = (std::cos(t0) - std::cos(t1)) * (2.0 * kPiSh / np);
      for (int j = 0; j < np; ++j) {
        const V w = unit_at(t, 2.0 * kPiSh * (j + 0.5) / np);
        const double cosine = w.x * n.x + w.y * n.y + w.z * n.z;
        if (cosine > 0.0) exact += sky(w).x * cosine * cell;
      }
    }
    const double estimate = sh9::irradiance(c, n).x;
    worst = std::max(worst, std::abs(estimate - exact));
  }
  std::printf("order-2 irradiance of a clamped sky: largest error %.5f (%.2f %% of the largest irradiance)\n", worst,
              100.0 * worst / (2.0 * kPiSh / 3.0));
  // The largest irradiance (normal straight up) is 2 pi / 3.
  EXPECT_LT(worst, 0.015 * (2.0 * kPiSh / 3.0));
  EXPECT_GT(worst, 1e-4);  // not band-limited: the estimate is not exact
}

// An equirectangular picture's texel directions are the inverse of facet's own mapping (the one
// the cube conversion reads pictures with), and a picture's light lands where that convention
// puts it: brighter above (1 + d.y) lights an upward normal by pi + 2 pi / 3; a bright patch at
// the picture's centre lights a normal looking along -Z.
TEST(Sh9, EquirectangularPicturesFollowFacetsConvention) {
  const int w = 256, h = 128;
  for (int r = 0; r < h; r += 7) {
    for (int c = 0; c < w; c += 11) {
      const V d = sh9::equirect_direction(c, r, w, h);
      const double dd[3] = {d.x, d.y, d.z};
      double u = 0.0, v = 0.0;
      equirect_coordinates(dd, u, v);
      EXPECT_NEAR(u, (c + 0.5) / w, 1e-12) << c << " " << r;
      EXPECT_NEAR(v, 1.0 - (r + 0.5) / h, 1e-12) << c << " " << r;  // v = 1 is the top row
    }
  }
  std::vector<float> sky(3 * w * h), patch(3 * w * h, 0.0f);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const V d = sh9::equirect_direction(c, r, w, h);
      for (int k = 0; k < 3; ++k) sky[3 * (r * w + c) + k] = static_cast<float>(1.0 + d.y);
      const bool centre = std::abs(c - w / 2) < 8 && std::abs(r - h / 2) < 8;
      patch[3 * (r * w + c)] = centre ? 50.0f : 0.0f;
    }
  }
  const sh9::Coefficients s = sh9::project_equirect(sky.data(), w, h);
  EXPECT_NEAR(sh9::irradiance(s, V{0.0, 1.0, 0.0}).x, kPiSh + 2.0 * kPiSh / 3.0, 1e-3);
  EXPECT_NEAR(sh9::irradiance(s, V{0.0, -1.0, 0.0}).x, kPiSh - 2.0 * kPiSh / 3.0, 1e-3);
  EXPECT_NEAR(sh9::irradiance(s, V{1.0, 0.0, 0.0}).x, kPiSh, 1e-3);
  const sh9::Coefficients p = sh9::project_equirect(patch.data(), w, h);
  const double front = sh9::irradiance(p, V{0.0, 0.0, -1.0}).x, back = sh9::irradiance(p, V{0.0, 0.0, 1.0}).x;
  const double right = sh9::irradiance(p, V{1.0, 0.0, 0.0}).x, up = sh9::irradiance(p, V{0.0, 1.0, 0.0}).x;
  EXPECT_GT(front, 0.0);
  EXPECT_GT(front, 4.0 * std::max({back, right, up}));
}

}  // namespace
}  // namespace facet::lighting
