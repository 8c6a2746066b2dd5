// The SIMD tile rasterizer against its scalar twin, on every ISA this CPU has:
//  - coverage, pixel by pixel, on random triangles from sub-pixel slivers to guard-band giants,
//    in tiles of every size at every image position (the 32-bit in-block edge test must agree
//    with the scalar 64-bit one everywhere, including |edge deltas| near 2^24);
//  - depth from the screen-space planes against the barycentric depth of the scalar path;
//  - block-linear tile layout, lazy clear and resolve: every format, orientation and odd size.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "io/image_convert.hpp"
#include "io/srgb.hpp"
#include "geometry/project.hpp"
#include "raster/assemble.hpp"
#include "tile/tile_raster.hpp"
#include "test_support.hpp"

namespace facet::raster {
namespace {

class SimdRaster : public ::testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "this CPU does not have " << to_string(GetParam());
    kernels_ = tile::simd_raster_kernels(GetParam());
    ASSERT_NE(kernels_, nullptr);
  }
  const tile::simd::Kernels* kernels_ = nullptr;
};

// A triangle placed by the renderer's own set-up (place_triangle, nothing culled), at constant
// depth `z`, flat colour `rgb`.
std::optional<ScreenTriangle> make_triangle(const std::int32_t (&x)[3], const std::int32_t (&y)[3], float z,
                                            int width, int height, float red = 1.0f) {
  ScreenTriangle t = ScreenTriangle::zeroed();
  for (int k = 0; k < 3; ++k) {
    t.x[k] = x[k], t.y[k] = y[k];
    t.z[k] = z;
    t.inv_w[k] = 1.0f;
  }
  bool swapped = false;
  if (place_triangle(t, CullMode::none, false, false, {width, height}, swapped) != Placement::placed) return std::nullopt;
  t.flat_rgb[0] = red;
  t.alpha = 1.0f;
  compute_planes(t, nullptr, 0);
  return t;
}

// Runs one tile with the kernels; returns the depth of each tile pixel (1 where nothing landed).
std::vector<float> raster_depth(const tile::simd::Kernels& k, std::span<const ScreenTriangle> triangles, const tile::TileRect& rect,
                                int tile_size, ShadingMode shading, tile::simd::TileCounters& counters) {
  tile::TileBuffers tile;
  tile.resize(tile_size);
  std::vector<std::uint32_t> bin(triangles.size());
  for (std::size_t i = 0; i < bin.size(); ++i) bin[i] = static_cast<std::uint32_t>(i);
  const ScreenTriangle* range = triangles.data();
  tile::simd::Draw draw;  // plain, flat: no varyings (every triangle here is object 0)
  draw.layout = plan_varyings(LitAt::triangle, false);
  const tile::simd::Fog fog;
  tile::simd::TileJob job{shading, &range, bin.data(), bin.size(), rect.x0, rect.y0, rect.x1, rect.y1,
                    nullptr, &draw, &fog};
  k.raster(job, tile.view({0, 0, 0, 1}, {}), counters);
  std::vector<float> depth(static_cast<std::size_t>(tile_size * tile_size), 1.0f);
  for (int y = 0; y < rect.y1 - rect.y0; ++y) {
    for (int x = 0; x < rect.x1 - rect.x0; ++x) {
      const std::size_t block = tile.index(x, y) / tile::simd::kBlockPixels;
      if (tile.touched[block]) depth[static_cast<std::size_t>(y * tile_size + x)] = tile.plane(4)[tile.index(x, y)];
    }
  }
  return depth;
}

TEST_P(SimdRaster, CoverageMatchesTheScalarRasterizerOnRandomTriangles) {
  std::mt19937_64 rng(2026);
  auto pick = [&](std::int64_t lo, std::int64_t hi) { return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng); };
  const int width = 4096, height = 2048;
  std::size_t triangles = 0, pixels = 0, mismatches = 0;
  for (int round = 0; round < 8000; ++round) {
    const int tile_size = 8 * static_cast<int>(pick(1, 32));
    const int tx = static_cast<int>(pick(0, width / tile_size - 1)), ty = static_cast<int>(pick(0, height / tile_size - 1));
    // Rects cut by the image border half of the time.
    const tile::TileRect rect{tx * tile_size, ty * tile_size, tx * tile_size + static_cast<int>(pick(1, tile_size)),
                        ty * tile_size + static_cast<int>(pick(1, tile_size))};
    // Scales from slivers inside one pixel to triangles spanning the +-32768 px guard band.
    const std::int64_t scales[] = {64, 1024, 8192, 65536, 1 << 20, std::int64_t(1) << 23};
    const std::int64_t s = scales[pick(0, 5)];
    const std::int64_t cx = (rect.x0 + tile_size / 2) * 256, cy = (rect.y0 + tile_size / 2) * 256;
    std::int32_t x[3], y[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = static_cast<std::int32_t>(std::clamp<std::int64_t>(cx + pick(-s, s), -(1 << 23), 1 << 23));
      y[k] = static_cast<std::int32_t>(std::clamp<std::int64_t>(cy + pick(-s, s), -(1 << 23), 1 << 23));
      if (pick(0, 3) == 0) x[k] = (x[k] >> 8) * 256 + 128;  // on pixel centres: the fill rule decides
      if (pick(0, 3) == 0) y[k] = (y[k] >> 8) * 256 + 128;
    }
    const auto t = make_triangle(x, y, 0.5f, width, height);
    if (!t) continue;
    ++triangles;
    std::vector<int> expected(static_cast<std::size_t>(tile_size * tile_size), 0);
    const int x0 = std::max(t->min_px, rect.x0), x1 = std::min(t->max_px, rect.x1 - 1);
    const int y0 = std::max(t->min_py, rect.y0), y1 = std::min(t->max_py, rect.y1 - 1);
    std::uint64_t expected_count = 0;
    if (x0 <= x1 && y0 <= y1) {
      for_each_covered_pixel(*t, x0, y0, x1, y1, [&](int px, int py, std::int64_t, std::int64_t, std::int64_t) {
        expected[static_cast<std::size_t>((py - rect.y0) * tile_size + (px - rect.x0))] = 1;
        ++expected_count;
      });
    }
    tile::simd::TileCounters counters;
    const std::vector<float> depth = raster_depth(*kernels_, std::span(&*t, 1), rect, tile_size, ShadingMode::flat, counters);
    for (std::size_t i = 0; i < depth.size(); ++i) {
      const int got = depth[i] < 1.0f ? 1 : 0;
      pixels += static_cast<std::size_t>(got);
      if (got != expected[i] && ++mismatches <= 5) {
        ADD_FAILURE() << "round " << round << ": tile pixel " << i % tile_size << "," << i / tile_size << " simd "
                      << got << " scalar " << expected[i];
      }
    }
    EXPECT_EQ(counters.tested, expected_count);
    EXPECT_EQ(counters.filled, expected_count);
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_GT(triangles, 6000u);
  EXPECT_GT(pixels, 1'000'000u);
}

TEST_P(SimdRaster, WatertightFanAroundEveryPixelCentreOfATile) {
  // Eight triangles around a shared vertex on a pixel centre, plus a sliver fan: every tile pixel
  // inside the fan's boundary is covered exactly once (counted through the depth test: a second
  // cover at the same depth fails LESS, so tested - filled counts double covers).
  const int size = 64;
  const std::int32_t c = 32 * 256 + 128;
  const std::int32_t r = 30 * 256;
  std::vector<ScreenTriangle> tris;
  const std::int32_t ring[8][2] = {{r, 0}, {r, r}, {0, r}, {-r, r}, {-r, 0}, {-r, -r}, {0, -r}, {r, -r}};
  for (int i = 0; i < 8; ++i) {
    const std::int32_t x[3] = {c, c + ring[i][0], c + ring[(i + 1) % 8][0]};
    const std::int32_t y[3] = {c, c + ring[i][1], c + ring[(i + 1) % 8][1]};
    if (auto t = make_triangle(x, y, 0.5f, size, size)) tris.push_back(*t);
  }
  tile::simd::TileCounters counters;
  const std::vector<float> depth = raster_depth(*kernels_, tris, {0, 0, size, size}, size, ShadingMode::flat, counters);
  EXPECT_EQ(counters.tested, counters.filled);  // nothing covered twice
  // The fan is the square [c - r, c + r]^2: pixel centres strictly inside, plus the top-left edges.
  std::uint64_t inside = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) inside += depth[static_cast<std::size_t>(y * size + x)] < 1.0f;
  EXPECT_EQ(inside, counters.filled);
  EXPECT_EQ(inside, 60u * 60u);
}

// Depth comes from a float plane (as on GPUs): the error is a few ulps of the largest term,
// |z| + 8 (|dz/dx| + |dz/dy|) (block-origin value plus in-block step) and the block origin's distance
// from vertex 0 times the gradient's rounding. Well-shaped triangles stay near 1e-7; slivers,
// whose planes are steep, lose in proportion to their gradient.
TEST_P(SimdRaster, PlaneDepthAgreesWithBarycentricDepth) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::int32_t> coord(0, 64 * 256);
  std::uniform_real_distribution<float> zd(0.0f, 1.0f);
  double worst_scaled = 0, worst_well_shaped = 0;
  std::size_t well_shaped = 0;
  for (int round = 0; round < 2000; ++round) {
    ScreenTriangle t = ScreenTriangle::zeroed();
    for (int k = 0; k < 3; ++k) {
      t.x[k] = coord(rng), t.y[k] = coord(rng);
      t.z[k] = zd(rng);
      t.inv_w[k] = 1.0f;
    }
    bool swapped = false;
    if (place_triangle(t, CullMode::none, false, false, {64, 64}, swapped) != Placement::placed) continue;
    compute_planes(t, nullptr, 0);
    const Plane& p = t.plane[kPlaneZ];
    const double gradient = std::abs(double(p.dx)) + std::abs(double(p.dy));
    // Well shaped: every side at least 8 px and an area of at least 100 px^2.
    bool good = double(signed_area2(t)) / 65536.0 / 2 >= 100;
    for (int k = 0; k < 3; ++k) {
      const double dx = (t.x[(k + 1) % 3] - t.x[k]) / 256.0, dy = (t.y[(k + 1) % 3] - t.y[k]) / 256.0;
      good = good && std::hypot(dx, dy) >= 8;
    }
    well_shaped += good;
    tile::simd::TileCounters counters;
    const std::vector<float> depth = raster_depth(*kernels_, std::span(&t, 1), {0, 0, 64, 64}, 64, ShadingMode::flat, counters);
    for_each_covered_pixel(t, t.min_px, t.min_py, t.max_px, t.max_py,
                           [&](int x, int y, std::int64_t e0, std::int64_t e1, std::int64_t e2) {
                             const double exact = (double(e0) * t.z[0] + double(e1) * t.z[1] + double(e2) * t.z[2]) /
                                                  double(signed_area2(t));
                             const double err = std::abs(depth[static_cast<std::size_t>(y * 64 + x)] - exact);
                             worst_scaled = std::max(worst_scaled, err / (1.0 + 80.0 * gradient));
                             if (good) worst_well_shaped = std::max(worst_well_shaped, err);
                           });
  }
  EXPECT_GT(well_shaped, 200u);
  EXPECT_LT(worst_well_shaped, 5e-7) << "well-shaped triangles";
  EXPECT_LT(worst_scaled, 4.0 * 0x1p-24) << "error / (1 + 80 |gradient|), all triangles";
  std::printf("depth error: %.3g on well-shaped triangles; %.3g x (1 + 80 |gradient|) on all\n", worst_well_shaped,
              worst_scaled);
}

// The SIMD resolve quantises each pixel to 8 bits itself (TileKernel::unorm8, in the ISA's
// template). Byte for byte, it must agree with to_unorm8 applied to the same pixel resolved as
// float: rendered twice, as 8-bit and as (non-HDR) RGBA32F, every channel of every pixel, for lit
// pixels in both interpolating modes and for the clear colour in untouched blocks. The clear
// colour sits on rounding boundaries (k + 0.5) / 255 and just below them. Both 8-bit layouts, both
// orientations, rows at an odd address, and a width of whole blocks (the fast resolve,
// TileKernel::resolve_unorm8, on avx512 16 pixels at a time) and one of a partial block (the
// general resolve).
TEST_P(SimdRaster, ResolveQuantisesExactlyLikeToUnorm8) {
  Scene scene = make_default_scene();
  for (ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
    for (float nudge : {0.0f, -1e-7f}) {
      for (PixelFormat format : {PixelFormat::rgba8, PixelFormat::bgra8}) {
        for (bool y_up : {false, true}) {
          for (std::size_t offset : {0, 1}) {
            for (int w : {96, 91}) {
              RenderOptions o = test::gl_options();
              o.path = LightingPath::simd;
              o.isa = GetParam();
              o.shading = shading;
              o.threads = 1;
              o.clear_color = {100.5f / 255.0f + nudge, 0.5f / 255.0f + nudge, 254.5f / 255.0f + nudge, 1.0f};
              const int h = 64;
              const std::string what = std::string(to_string(shading)) + " nudge " + std::to_string(nudge) + " " +
                                       to_string(format) + (y_up ? " y-up" : "") + " offset " +
                                       std::to_string(offset) + " width " + std::to_string(w);
              std::vector<std::uint8_t> storage(static_cast<std::size_t>(w) * h * 4 + offset);
              std::uint8_t* bytes = storage.data() + offset;
              std::vector<float> floats(static_cast<std::size_t>(w) * h * 4);
              const ImageView as_bytes{bytes, w, h, static_cast<std::size_t>(w) * 4, format, y_up};
              const ImageView as_floats{reinterpret_cast<std::uint8_t*>(floats.data()), w, h,
                                        static_cast<std::size_t>(w) * 16, PixelFormat::rgba32f, false};
              Renderer r(o);
              ASSERT_TRUE(r.render(scene, as_bytes).ok());
              ASSERT_TRUE(r.render(scene, as_floats).ok());
              int mismatches = 0, lit = 0;
              for (int y = 0; y < h; ++y) {
                const std::uint8_t* row = bytes + static_cast<std::size_t>(y_up ? h - 1 - y : y) * w * 4;
                for (int x = 0; x < w; ++x) {
                  const float* px = floats.data() + (static_cast<std::size_t>(y) * w + x) * 4;
                  for (int c = 0; c < 4; ++c) {
                    const int byte = format == PixelFormat::bgra8 && c != 1 && c != 3 ? 2 - c : c;
                    if (row[4 * x + byte] != to_unorm8(px[c])) ++mismatches;
                  }
                  if (px[0] != o.clear_color[0]) ++lit;
                }
              }
              EXPECT_EQ(mismatches, 0) << what;
              EXPECT_GT(lit, w * h / 10) << "the scene must cover part of the image";
              EXPECT_LT(lit, w * h) << "and leave some of the clear colour";
            }
          }
        }
      }
    }
  }
}

// The resolve's sRGB encoding (SrgbTable's buckets and two gathers a channel) against the
// threshold search of io/srgb.hpp, byte for byte: every threshold, the floats either side of it,
// the first float of every bucket and the one before it, 2^-13 and 1 and their neighbours, zeros,
// negatives, values above 1, infinities and NaN, as red, green and blue of touched blocks; through
// the fast resolve (whole blocks) and the general one (a partial block, and with a depth view).
TEST_P(SimdRaster, ResolveEncodesSrgbLikeTheThresholdSearch) {
  SrgbTable table;
  make_srgb_table(table);
  std::vector<float> values = {0.0f, -0.0f, -1.0f, 0x1p-13f, std::nextafter(0x1p-13f, 0.0f), std::nextafter(0x1p-13f, 1.0f),
                               1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 2.0f), 7.0f, 1e-30f,
                               std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                               std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min()};
  for (int k = 1; k < 256; ++k) {
    values.push_back(table.threshold[k]);
    values.push_back(std::nextafter(table.threshold[k], -1.0f));
    values.push_back(std::nextafter(table.threshold[k], 2.0f));
  }
  for (int b = 0; b <= SrgbTable::kBuckets; ++b) {
    const float first = std::bit_cast<float>((b + SrgbTable::kBucketBias) << SrgbTable::kBucketShift);
    values.push_back(first);
    values.push_back(std::nextafter(first, 0.0f));
  }
  const int size = 64;
  ASSERT_LE(values.size(), std::size_t{3} * size * size);
  tile::TileBuffers tile;
  tile.resize(size);
  std::fill(tile.touched.begin(), tile.touched.end(), std::uint8_t{1});
  const geometry::DepthFormat depth_format{};
  std::size_t next = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      for (int c = 0; c < 3; ++c) tile.plane(c)[tile.index(x, y)] = values[next++ % values.size()];
      tile.plane(3)[tile.index(x, y)] = 1.0f;
      tile.plane(4)[tile.index(x, y)] = 0.5f;
    }
  }
  for (int w : {size, size - 3}) {
    for (bool with_depth : {false, true}) {
      std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size) * size * 4);
      std::vector<float> depth(static_cast<std::size_t>(size) * size);
      const ImageView image{bytes.data(), size, size, static_cast<std::size_t>(size) * 4, PixelFormat::rgba8, false};
      const DepthView depth_view{depth.data(), size, size, static_cast<std::size_t>(size) * 4, false};
      kernels_->resolve(tile.view({0, 0, 0, 1}, depth_format, &table), 0, 0, w, size, image, with_depth ? &depth_view : nullptr);
      int mismatches = 0;
      for (int y = 0; y < size; ++y) {
        for (int x = 0; x < w; ++x) {
          for (int c = 0; c < 3; ++c) {
            const float v = tile.plane(c)[tile.index(x, y)];
            const int got = bytes[(static_cast<std::size_t>(y) * size + x) * 4 + c];
            if (got != srgb_unorm8_search(table.threshold, v)) {
              if (++mismatches < 5) ADD_FAILURE() << "value " << v << ": " << got << ", not " << int(srgb_unorm8_search(table.threshold, v));
            }
          }
        }
      }
      EXPECT_EQ(mismatches, 0) << "width " << w << (with_depth ? " with depth" : "");
    }
  }
}

// The display pass's store (Kernels::display_row) against the scalar definition, byte for byte:
// background pixels (far depth and exactly the clear colour) clamped and encoded, the others
// scaled, tone-mapped by facet::tone_map and encoded; for every operator, linear and sRGB, RGBA8 and
// BGRA8, on random values from 1e-4 to 100 (both of Neutral's branches), zeros, negatives,
// infinities and NaN; a width that is not a whole number of batches (the kernel leaves the tail).
TEST_P(SimdRaster, DisplayStoreIsTheScalarToneMapAndEncoding) {
  SrgbTable table;
  make_srgb_table(table);
  const int w = 1003;
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> exponent(-4.0f, 2.0f);
  const float clear[4] = {0.25f, 0.5f, 0.75f, 1.0f};
  std::vector<float> rgba(4 * static_cast<std::size_t>(w)), depth(w);
  const float specials[] = {0.0f, -0.0f, -3.0f, std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(), 0.079f, 0.08f, 0.76f, 1.0f};
  for (int x = 0; x < w; ++x) {
    for (int c = 0; c < 4; ++c) rgba[4 * x + c] = std::pow(10.0f, exponent(rng));
    if (x % 7 == 0) rgba[4 * x + x % 3] = specials[(x / 7) % std::size(specials)];
    if (x % 5 == 0) rgba[4 * x + 3] = 1.0f;
    depth[x] = x % 4 == 0 ? 1.0f : 0.5f;
    if (x % 8 == 0) {  // background (depth far as well: x % 4 == 0)
      for (int c = 0; c < 4; ++c) rgba[4 * x + c] = clear[c];
    }
    if (x % 24 == 12) rgba[4 * x] = clear[0] + 0.5f;  // far, but not the clear colour: drawn
  }
  for (const ToneMapping op : {ToneMapping::none, ToneMapping::neutral, ToneMapping::aces}) {
    for (const bool srgb : {false, true}) {
      for (const int red : {0, 2}) {
        std::vector<std::uint8_t> out(4 * static_cast<std::size_t>(w), 0xAB);
        const float scale = 1.7f;
        const tile::simd::DisplayRow row{rgba.data(), depth.data(), w, 1.0f, {clear[0], clear[1], clear[2], clear[3]}, scale, op,
                                         srgb ? &table : nullptr, red, out.data()};
        const int done = kernels_->display_row(row);
        ASSERT_GT(done, w - 16);
        ASSERT_LE(done, w);
        auto encode = [&](float v) { return srgb ? int(srgb_unorm8_search(table.threshold, v)) : int(to_unorm8(v)); };
        int mismatches = 0;
        for (int x = 0; x < done; ++x) {
          const float* p = rgba.data() + 4 * x;
          const bool background = depth[x] == 1.0f && p[0] == clear[0] && p[1] == clear[1] && p[2] == clear[2] && p[3] == clear[3];
          std::array<float, 3> t{};
          if (background) {
            for (int c = 0; c < 3; ++c) t[c] = std::clamp(p[c], 0.0f, 1.0f);
          } else {
            t = tone_map(op, {p[0] * scale, p[1] * scale, p[2] * scale});
          }
          const int expected[4] = {encode(t[0]), encode(t[1]), encode(t[2]), to_unorm8(p[3])};
          for (int c = 0; c < 4; ++c) {
            const int byte = red == 2 && c != 1 && c != 3 ? 2 - c : c;
            if (out[4 * x + byte] != expected[c] && ++mismatches < 5) {
              ADD_FAILURE() << to_string(op) << (srgb ? " srgb" : " linear") << " red " << red << " pixel " << x << " channel " << c
                            << " value " << p[c] << ": " << int(out[4 * x + byte]) << ", not " << expected[c];
            }
          }
        }
        EXPECT_EQ(mismatches, 0);
        if (done < w) {
          EXPECT_EQ(out[4 * static_cast<std::size_t>(done)], 0xAB);  // the tail is the caller's
        }
      }
    }
  }
}

// The ISA's vertex transform (Kernels::transform) against geometry::transform_vertices, bit for
// bit: clip positions, outcodes, the finite and projected flags and, where projected, the snapped
// position, depth and 1/w (coverage is decided by them). Vertices in front of, behind and on the
// camera plane, on and across the frustum and guard band, far outside, huge, infinite and NaN,
// through a perspective and a random matrix, in ranges that start and end off the batch width.
TEST_P(SimdRaster, VertexTransformIsTheScalarOneBitForBit) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Vec3> positions;
  const float specials[] = {0.0f, -0.0f, 1e-30f, 1e30f, -1e30f, 3e38f, std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()};
  for (float s : specials) {
    positions.emplace_back(s, 0.5f, -5.0f);
    positions.emplace_back(0.5f, s, -5.0f);
    positions.emplace_back(0.5f, 0.5f, s);
  }
  for (int i = 0; i < 4000; ++i) {
    const float scale = std::pow(10.0f, 4.0f * unit(rng));  // 1e-4 .. 1e4
    positions.emplace_back(scale * unit(rng), scale * unit(rng), scale * unit(rng));
  }
  for (int i = 0; i < 500; ++i) positions.emplace_back(unit(rng), unit(rng), 0.1f * unit(rng));  // around the near plane
  Camera camera;
  camera.eye = Vec3(0, 0, 0);
  camera.target = Vec3(0, 0, -1);
  camera.near = 0.1f;
  camera.far = 100.0f;
  const Eigen::Matrix4d view_proj = (projection_matrix(camera, 16.0f / 9.0f) * view_matrix(camera)).cast<double>();
  geometry::Mat4Rows perspective{}, random{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      perspective.m[4 * r + c] = static_cast<float>(view_proj(r, c));
      random.m[4 * r + c] = 3.0f * unit(rng);
    }
  }
  const geometry::Viewport viewport{1920, 1080};
  const geometry::ClipPlanes planes = geometry::guard_band_planes(viewport);
  for (const geometry::Mat4Rows& mvp : {perspective, random}) {
    for (auto [begin, end] : {std::pair<std::size_t, std::size_t>{0, positions.size()}, {3, positions.size() - 5}, {1, 2}}) {
      std::vector<std::array<float, 4>> clip_a(positions.size()), clip_b(positions.size());
      std::vector<geometry::ScreenVertex> screen_a(positions.size()), screen_b(positions.size());
      geometry::transform_vertices(mvp, positions.data(), begin, end, planes, viewport, clip_a.data(), screen_a.data());
      kernels_->transform(mvp, positions.data()->data(), begin, end, planes, viewport, clip_b.data(), screen_b.data());
      int mismatches = 0, projected = 0, outside = 0;
      for (std::size_t i = begin; i < end; ++i) {
        const geometry::ScreenVertex &a = screen_a[i], &b = screen_b[i];
        bool same = std::memcmp(clip_a[i].data(), clip_b[i].data(), sizeof clip_a[i]) == 0 && a.finite == b.finite &&
                    a.frustum == b.frustum && a.guard == b.guard && a.projected == b.projected;
        if (same && a.projected) {
          same = a.x == b.x && a.y == b.y && std::memcmp(&a.z, &b.z, 4) == 0 && std::memcmp(&a.inv_w, &b.inv_w, 4) == 0;
        }
        if (!same && ++mismatches <= 3) ADD_FAILURE() << "vertex " << i << " (" << positions[i].transpose() << ")";
        projected += a.projected ? 1 : 0;
        outside += a.finite && a.guard != 0 ? 1 : 0;
      }
      EXPECT_EQ(mismatches, 0) << "range " << begin << ".." << end;
      if (end - begin > 1000) {
        EXPECT_GT(projected, 100) << "the test must project vertices";
        EXPECT_GT(outside, 100) << "and have vertices outside the guard band";
      }
    }
  }
}

// Placing (assemble.hpp) with the ISA's kernel, 16 triangles at a time, against the scalar twin:
// the same fates, counters, pending lists, vertex marks and record fields, bit for bit, in every
// cull mode, mirrored or not, two-sided or not. The triangles range from sub-pixel slivers and
// exact degenerates to giants wider than the kernel's 2^15 sub-pixel limit (handed to the scalar
// code), with vertices that are non-finite, outside the frustum or across the guard band.
TEST_P(SimdRaster, PlacingIsTheScalarOneBitForBit) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Mesh mesh;
  const float specials[] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(), 1e30f};
  for (float s : specials) mesh.positions.emplace_back(s, 0.5f, -5.0f);
  for (int i = 0; i < 3000; ++i) {  // clusters of three: triangles from 1e-4 to 10 units across
    const Vec3 centre(4.0f * unit(rng), 3.0f * unit(rng), -6.0f + 5.5f * unit(rng));
    const float size = std::pow(10.0f, 2.5f * unit(rng) - 1.5f);
    for (int k = 0; k < 3; ++k) mesh.positions.push_back(centre + size * Vec3(unit(rng), unit(rng), unit(rng)));
  }
  const auto n = static_cast<std::uint32_t>(mesh.positions.size());
  std::uniform_int_distribution<std::uint32_t> any(0, n - 1);
  for (std::uint32_t c = 3; c + 2 < n; c += 3) {
    mesh.triangles.push_back({c, c + 1, c + 2});
    mesh.triangles.push_back({c, c + 2, c + 1});
  }
  for (int i = 0; i < 600; ++i) mesh.triangles.push_back({any(rng), any(rng), any(rng)});  // anywhere, non-finite
  for (int i = 0; i < 100; ++i) {
    const std::uint32_t v = any(rng);
    mesh.triangles.push_back({v, v, any(rng)});  // zero area
  }
  mesh.triangles.push_back({0, 1, 2});
  Camera camera;
  camera.eye = Vec3(0, 0, 0);
  camera.target = Vec3(0, 0, -1);
  camera.near = 0.5f;
  camera.far = 10.0f;
  const Eigen::Matrix4d view_proj = (projection_matrix(camera, 16.0f / 9.0f) * view_matrix(camera)).cast<double>();
  geometry::Mat4Rows mvp{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) mvp.m[4 * r + c] = static_cast<float>(view_proj(r, c));
  }
  AssemblyFrame frame;
  frame.viewport = {1920, 1080};
  frame.planes = geometry::guard_band_planes(frame.viewport);
  frame.grid = {64, 30, 17};
  std::vector<std::array<float, 4>> clip(n);
  std::vector<geometry::ScreenVertex> screen(n);
  geometry::transform_vertices(mvp, mesh.positions.data(), 0, n, frame.planes, frame.viewport, clip.data(), screen.data());
  ObjectVertices object;
  object.layout = plan_varyings(LitAt::triangle, false);
  object.clip = clip;
  object.screen = screen;

  struct Result {
    std::vector<ScreenTriangle> out;
    RangeBinning binning;
    PendingTriangles pending;
    std::vector<std::uint8_t> drawn;
  };
  auto place = [&](simd::PlaceFunction kernel, std::size_t begin, std::size_t end) {
    Result r;
    r.drawn.assign(n, 0);
    frame.place = kernel;
    place_range(frame, mesh, object, begin, end, r.out, r.binning, r.pending, r.drawn.data());
    return r;
  };
  TriangleCounts seen;
  int wide = 0;
  for (const CullMode cull : {CullMode::back, CullMode::none, CullMode::front}) {
    for (const bool two_sided : {false, true}) {
      for (const bool mirrored : {false, true}) {
        frame.cull = cull;
        frame.two_sided = two_sided;
        object.mirrored = mirrored;
        for (auto [begin, end] : {std::pair<std::size_t, std::size_t>{0, mesh.triangles.size()}, {5, 5 + 37}}) {
          const Result a = place(nullptr, begin, end), b = place(kernels_->place, begin, end);
          const TriangleCounts &ca = a.binning.counts, &cb = b.binning.counts;
          EXPECT_EQ(std::tie(ca.in, ca.nonfinite, ca.outside, ca.clipped, ca.culled, ca.degenerate, ca.small),
                    std::tie(cb.in, cb.nonfinite, cb.outside, cb.clipped, cb.culled, cb.degenerate, cb.small));
          EXPECT_EQ(a.pending.triangle, b.pending.triangle);
          EXPECT_EQ(a.pending.kind, b.pending.kind);
          ASSERT_EQ(a.pending.depth.size(), b.pending.depth.size());  // z and 1/w, kept for the planes: bit for bit
          EXPECT_EQ(std::memcmp(a.pending.depth.data(), b.pending.depth.data(), a.pending.depth.size() * sizeof a.pending.depth[0]), 0);
          EXPECT_EQ(a.drawn, b.drawn);
          ASSERT_EQ(a.out.size(), b.out.size());
          int mismatches = 0;
          for (std::size_t i = 0; i < a.out.size(); ++i) {
            const ScreenTriangle &p = a.out[i], &q = b.out[i];
            const bool same = std::memcmp(p.x, q.x, sizeof p.x) == 0 && std::memcmp(p.y, q.y, sizeof p.y) == 0 &&
                              std::memcmp(p.bias, q.bias, sizeof p.bias) == 0 && p.min_px == q.min_px &&
                              p.min_py == q.min_py && p.max_px == q.max_px && p.max_py == q.max_py &&
                              p.back_facing() == q.back_facing();
            if (!same && ++mismatches <= 3) ADD_FAILURE() << "record " << i << " (triangle " << a.pending.triangle[i] << ")";
            const auto extent = std::max({std::abs(p.x[1] - p.x[0]), std::abs(p.x[2] - p.x[0]),
                                          std::abs(p.y[1] - p.y[0]), std::abs(p.y[2] - p.y[0])});
            wide += extent >= (1 << 15) ? 1 : 0;
          }
          EXPECT_EQ(mismatches, 0) << "cull " << int(cull) << " two-sided " << two_sided << " mirrored " << mirrored;
          seen.nonfinite += ca.nonfinite, seen.outside += ca.outside, seen.clipped += ca.clipped;
          seen.culled += ca.culled, seen.degenerate += ca.degenerate, seen.small += ca.small;
          seen.drawn += a.out.size();
        }
      }
    }
  }
  // Every fate, and triangles too wide for the kernel's 32-bit area, must have been met.
  EXPECT_GT(seen.nonfinite, 0u);
  EXPECT_GT(seen.outside, 0u);
  EXPECT_GT(seen.clipped, 0u);
  EXPECT_GT(seen.culled, 0u);
  EXPECT_GT(seen.degenerate, 0u);
  EXPECT_GT(seen.small, 0u);
  EXPECT_GT(seen.drawn, 1000u);
  EXPECT_GT(wide, 10);
}

INSTANTIATE_TEST_SUITE_P(Isas, SimdRaster, ::testing::Values(Isa::sse2, Isa::avx2, Isa::avx512),
                         [](const ::testing::TestParamInfo<Isa>& p) { return std::string(to_string(p.param)); });

}  // namespace
}  // namespace facet::raster
