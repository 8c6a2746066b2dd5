// Cube faces from an equirectangular picture (cube_faces_from_equirect): every face texel against
// the exact colour of its direction, the faces a mirror ball shows against exact reflection rays
// into the picture, the poles, 1x1 pictures and faces, and the refusals.
#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "facet/texture.hpp"
#include "texture/sampler.hpp"

namespace facet {
namespace {

// A smooth sky: each channel an affine function of the unit direction.
std::array<double, 3> sky_colour(const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = d.normalized();
  return {0.5 + 0.45 * u.x(), 0.5 + 0.45 * u.y(), 0.5 + 0.45 * u.z()};
}

// The direction at picture coordinates (u, v): the inverse of equirect_coordinates.
Eigen::Vector3d picture_direction(double u, double v) {
  const double phi = (u - 0.5) * 2.0 * M_PI, lat = (v - 0.5) * M_PI;
  return {std::cos(lat) * std::sin(phi), std::sin(lat), -std::cos(lat) * std::cos(phi)};
}

// A w x h equirectangular picture of the sky (top row first, as make_texture takes it).
Texture sky_picture(int w, int h) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h) * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const auto c = sky_colour(picture_direction((x + 0.5) / w, 1.0 - (y + 0.5) / h));
      std::uint8_t* p = &rgba[static_cast<std::size_t>(y * w + x) * 4];
      for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(255.0 * c[static_cast<std::size_t>(k)]));
      p[3] = 255;
    }
  }
  Result<Texture> t = make_texture("sky", w, h, rgba);
  EXPECT_TRUE(t.ok()) << t.status().message();
  return std::move(*t);
}

// GL 2.1 table 3.21: the direction through (s, t) of face f, t from the face's bottom row.
Eigen::Vector3d face_direction_from_bottom(int f, double s, double t) {
  const double sc = 2 * s - 1, tc = 1 - 2 * t;
  const Eigen::Vector3d d[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc}, {sc, -1, -tc}, {sc, -tc, 1}, {-sc, -tc, -1}};
  return d[f];
}

// A face texel (i, j from the bottom) as 0..255 per channel.
std::array<int, 4> texel(const Texture& t, int i, int j) {
  const std::uint32_t w = t.texels[static_cast<std::size_t>(j * t.width() + i)];
  return {int(w & 255), int(w >> 8 & 255), int(w >> 16 & 255), int(w >> 24)};
}

TEST(EquirectToCube, EveryFaceTexelShowsItsDirection) {
  const Texture picture = sky_picture(256, 128);
  Result<std::vector<Texture>> faces = cube_faces_from_equirect(picture, 32, "sky");
  ASSERT_TRUE(faces.ok()) << faces.status().message();
  ASSERT_EQ(faces->size(), 6u);
  double largest = 0, sum = 0;
  int n = 0;
  for (int f = 0; f < 6; ++f) {
    const Texture& face = (*faces)[static_cast<std::size_t>(f)];
    ASSERT_EQ(face.width(), 32);
    ASSERT_EQ(face.height(), 32);
    EXPECT_TRUE(validate_texture(face).ok());
    for (int j = 0; j < 32; ++j) {
      for (int i = 0; i < 32; ++i) {
        const auto want = sky_colour(face_direction_from_bottom(f, (i + 0.5) / 32, (j + 0.5) / 32));
        const auto got = texel(face, i, j);
        for (int c = 0; c < 3; ++c) {
          const double d = std::abs(got[static_cast<std::size_t>(c)] - 255.0 * want[static_cast<std::size_t>(c)]);
          largest = std::max(largest, d);
          sum += d;
          ++n;
        }
        EXPECT_EQ(got[3], 255);
      }
    }
  }
  // The box filter over a texel's footprint of a function affine in the unit direction differs
  // from its value at the texel's centre by the direction's curvature over the texel.
  EXPECT_LE(largest, 1.2) << "mean " << sum / n;
  EXPECT_LE(sum / n, 0.35);
}

TEST(EquirectToCube, PolesAndOneTexelFacesAreTheMeansOfTheirFaces) {
  const Texture picture = sky_picture(64, 32);
  Result<std::vector<Texture>> faces = cube_faces_from_equirect(picture, 1, "sky");
  ASSERT_TRUE(faces.ok());
  for (int f = 0; f < 6; ++f) {
    // The mean of the sky over the face, in double over a fine grid.
    std::array<double, 3> mean{};
    const int g = 64;
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i) {
        const auto c = sky_colour(face_direction_from_bottom(f, (i + 0.5) / g, (j + 0.5) / g));
        for (int k = 0; k < 3; ++k) mean[static_cast<std::size_t>(k)] += c[static_cast<std::size_t>(k)] / (g * g);
      }
    const auto got = texel((*faces)[static_cast<std::size_t>(f)], 0, 0);
    for (int c = 0; c < 3; ++c) {
      // 4 x 4 samples of a face that spans a quarter turn: the mean within 3 steps.
      EXPECT_NEAR(got[static_cast<std::size_t>(c)], 255.0 * mean[static_cast<std::size_t>(c)], 3.0) << "face " << f << " channel " << c;
    }
  }
  // A 1x1 picture: every face texel its colour, at any size.
  const std::uint8_t one[4] = {10, 200, 30, 128};
  Result<Texture> dot = make_texture("dot", 1, 1, one);
  ASSERT_TRUE(dot.ok());
  faces = cube_faces_from_equirect(*dot, 5, "dot");
  ASSERT_TRUE(faces.ok());
  for (const Texture& face : *faces)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) EXPECT_EQ(texel(face, i, j), (std::array<int, 4>{10, 200, 30, 128}));
}

TEST(EquirectToCube, NeverFiltersAcrossAPole) {
  // The picture's top half white, its bottom half black (4 rows: row centres at latitudes +-22.5
  // and +-67.5 degrees): every direction of the +Y face reads white rows only and every direction
  // of the -Y face black ones, so a filter that wrapped over a pole would show.
  std::vector<std::uint8_t> rgba(8 * 4 * 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      std::uint8_t* p = &rgba[static_cast<std::size_t>(y * 8 + x) * 4];
      p[0] = p[1] = p[2] = y < 2 ? 255 : 0;  // top row first
      p[3] = 255;
    }
  Result<Texture> picture = make_texture("poles", 8, 4, rgba);
  ASSERT_TRUE(picture.ok());
  Result<std::vector<Texture>> faces = cube_faces_from_equirect(*picture, 16, "poles");
  ASSERT_TRUE(faces.ok());
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      EXPECT_EQ(texel((*faces)[2], i, j)[0], 255) << i << ", " << j;
      EXPECT_EQ(texel((*faces)[3], i, j)[0], 0) << i << ", " << j;
    }
  }
}

TEST(EquirectToCube, CoordinatesOfTheAxes) {
  auto at = [](double x, double y, double z) {
    const double d[3] = {x, y, z};
    double u, v;
    equirect_coordinates(d, u, v);
    return std::array<double, 2>{u, v};
  };
  EXPECT_NEAR(at(0, 0, -1)[0], 0.5, 1e-12);   // the picture's centre looks along -Z
  EXPECT_NEAR(at(1, 0, 0)[0], 0.75, 1e-12);   // +X a quarter turn to its right
  EXPECT_NEAR(at(-1, 0, 0)[0], 0.25, 1e-12);
  EXPECT_NEAR(at(0, 1, 0)[1], 1.0, 1e-12);    // +Y at the top
  EXPECT_NEAR(at(0, -1, 0)[1], 0.0, 1e-12);
  EXPECT_NEAR(at(0, 0, 0)[1], 0.5, 1e-12);    // a zero direction: finite
}

TEST(EquirectToCube, RefusesBadSizesAndBudgets) {
  const Texture picture = sky_picture(8, 4);
  Result<std::vector<Texture>> r = cube_faces_from_equirect(picture, 0, "p");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::invalid_argument);
  EXPECT_EQ(r.status().field(), "face_size");
  r = cube_faces_from_equirect(picture, kEquirectMaxFace + 1, "p");
  EXPECT_FALSE(r.ok());
  TextureOptions small;
  small.memory_budget_bytes = 6 * 16 * 16 * 4 - 1;
  small.filter = TextureFilter::bilinear;
  r = cube_faces_from_equirect(picture, 16, "p", small);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::out_of_memory);
  small.memory_budget_bytes = 6 * 16 * 16 * 4;
  EXPECT_TRUE(cube_faces_from_equirect(picture, 16, "p", small).ok());
  Texture broken = picture;
  broken.texels.pop_back();
  EXPECT_FALSE(cube_faces_from_equirect(broken, 4, "p").ok());
}

}  // namespace
}  // namespace facet
