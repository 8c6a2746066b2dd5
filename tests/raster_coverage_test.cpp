// Coverage of the fixed-point rasterizer: the top-left rule case by case, and watertightness on
// 10^5 random closed meshes (fans and grids) checked against an exact point-in-polygon test, for
// the scalar rasterizer and for the SIMD tile kernels of every ISA this CPU has.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "raster/assemble.hpp"
#include "raster/bins.hpp"
#include "tile/tile_raster.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::raster {
namespace {

struct P {
  std::int64_t x, y;  // fixed point, 8 sub-pixel bits
};

P centre_of(int px, int py) { return {px * 256 + 128, py * 256 + 128}; }

// Oriented and set up by the renderer's own set-up (place_triangle, nothing culled).
std::optional<ScreenTriangle> setup(P a, P b, P c, int width, int height) {
  ScreenTriangle t = ScreenTriangle::zeroed();
  const P v[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    t.x[k] = static_cast<std::int32_t>(v[k].x);
    t.y[k] = static_cast<std::int32_t>(v[k].y);
  }
  bool swapped = false;
  if (place_triangle(t, CullMode::none, false, false, {width, height}, swapped) != Placement::placed) return std::nullopt;
  return t;
}

// Counts how often each pixel is covered, with the scalar rasterizer or (kernels != null) with a
// SIMD tile kernel: one triangle per run over the whole w x h tile, covered pixels read back from
// the depth plane.
class Coverage {
 public:
  Coverage(int w, int h, const tile::simd::Kernels* kernels = nullptr)
      : w_(w), h_(h), count_(static_cast<std::size_t>(w * h), 0), kernels_(kernels) {
    tile_.resize(w);
  }
  void add(P a, P b, P c) {
    auto t = setup(a, b, c, w_, h_);
    if (!t) return;
    if (!kernels_) {
      for_each_covered_pixel(*t, t->min_px, t->min_py, t->max_px, t->max_py,
                             [&](int x, int y, std::int64_t, std::int64_t, std::int64_t) { ++at(x, y); });
      return;
    }
    for (auto& z : t->z) z = 0.5f;
    for (auto& w : t->inv_w) w = 1.0f;
    compute_planes(*t, nullptr, 0);
    const ScreenTriangle* range = &*t;
    const std::uint32_t bin = 0;
    tile::simd::Draw draw;  // plain, flat: no varyings (the triangle is object 0)
    draw.layout = plan_varyings(LitAt::triangle, false);
    const tile::simd::Fog fog;
    tile::simd::TileJob job{ShadingMode::flat, &range, &bin, 1, 0, 0, w_, h_, nullptr, &draw, &fog};
    tile::simd::TileCounters counters;
    kernels_->raster(job, tile_.view({0, 0, 0, 1}, {}), counters);
    std::uint64_t found = 0;
    for (int y = t->min_py; y <= t->max_py; ++y) {
      for (int x = t->min_px; x <= t->max_px; ++x) {
        const std::size_t i = tile_.index(x, y);
        if (tile_.touched[i / tile::simd::kBlockPixels] && tile_.plane(4)[i] < 1.0f) ++at(x, y), ++found;
      }
    }
    // Every pixel the kernel counted lies inside the triangle's bounds.
    if (found != counters.tested) ADD_FAILURE() << "covered pixels outside the triangle's bounds";
  }
  int& at(int x, int y) { return count_[static_cast<std::size_t>(y * w_ + x)]; }
  void clear(int x0, int y0, int x1, int y1) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) at(x, y) = 0;
  }
  int w() const { return w_; }
  int h() const { return h_; }

 private:
  int w_, h_;
  std::vector<int> count_;
  const tile::simd::Kernels* kernels_;
  tile::TileBuffers tile_;
};

// --- The top-left rule, case by case (y grows downwards; pixel (x, y) has its centre at
// (256x + 128, 256y + 128)).

TEST(TopLeftRule, PixelCentreOnTopEdgeIsCovered) {
  Coverage c(8, 8);
  c.add({0, 128}, {1024, 128}, {0, 1024});  // horizontal edge through row 0's centres, interior below
  EXPECT_EQ(c.at(1, 0), 1);
}

TEST(TopLeftRule, PixelCentreOnBottomEdgeIsNotCovered) {
  Coverage c(8, 8);
  c.add({0, 0}, {1024, 640}, {0, 640});  // horizontal edge through row 2's centres, interior above
  EXPECT_EQ(c.at(1, 2), 0);
  EXPECT_EQ(c.at(1, 1), 1);
}

TEST(TopLeftRule, PixelCentreOnLeftEdgeIsCovered) {
  Coverage c(8, 8);
  c.add({384, 0}, {1024, 512}, {384, 1024});  // vertical edge through column 1's centres, interior right
  EXPECT_EQ(c.at(1, 1), 1);
  EXPECT_EQ(c.at(1, 2), 1);
}

TEST(TopLeftRule, PixelCentreOnRightEdgeIsNotCovered) {
  Coverage c(8, 8);
  c.add({384, 0}, {384, 1024}, {0, 512});  // vertical edge through column 1's centres, interior left
  EXPECT_EQ(c.at(1, 1), 0);
  EXPECT_EQ(c.at(0, 2), 1);
}

TEST(TopLeftRule, SharedDiagonalThroughPixelCentresIsCoveredOnce) {
  Coverage c(8, 8);
  const P a = centre_of(0, 0), b = centre_of(4, 0), d = centre_of(4, 4), e = centre_of(0, 4);
  c.add(a, b, d);
  c.add(a, d, e);  // the diagonal a-d passes through the centres of (1,1), (2,2), (3,3)
  for (int i = 1; i <= 3; ++i) EXPECT_EQ(c.at(i, i), 1) << i;
}

TEST(TopLeftRule, FanAroundAPixelCentreCoversItOnce) {
  Coverage c(8, 8);
  const P m = centre_of(3, 3);
  const P ring[6] = {{m.x + 600, m.y}, {m.x + 300, m.y + 520}, {m.x - 300, m.y + 520},
                     {m.x - 600, m.y}, {m.x - 300, m.y - 520}, {m.x + 300, m.y - 520}};
  for (int i = 0; i < 6; ++i) c.add(m, ring[i], ring[(i + 1) % 6]);
  EXPECT_EQ(c.at(3, 3), 1);
}

TEST(TopLeftRule, WindingDoesNotChangeCoverage) {
  Coverage cw(8, 8), ccw(8, 8);
  const P a{100, 50}, b{1500, 700}, d{300, 1800};
  cw.add(a, b, d);
  ccw.add(a, d, b);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(cw.at(x, y), ccw.at(x, y));
}

TEST(TopLeftRule, ZeroAreaCoversNothing) {
  Coverage c(8, 8);
  c.add(centre_of(0, 0), centre_of(3, 3), centre_of(6, 6));  // collinear through pixel centres
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(c.at(x, y), 0);
}

// --- Watertightness.

// Exact winding number of `poly` around q; nullopt when q lies on the boundary.
std::optional<int> winding(const std::vector<P>& poly, P q) {
  int wn = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const P a = poly[i], b = poly[(i + 1) % poly.size()];
    const std::int64_t left = (b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y);
    if (left == 0 && std::min(a.x, b.x) <= q.x && q.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= q.y &&
        q.y <= std::max(a.y, b.y)) {
      return std::nullopt;
    }
    if (a.y <= q.y) {
      if (b.y > q.y && left > 0) ++wn;
    } else if (b.y <= q.y && left < 0) {
      --wn;
    }
  }
  return wn;
}

std::int64_t area2(const std::array<P, 3>& t) {
  return (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
}

struct Mesh2D {
  std::vector<std::array<P, 3>> triangles;
  std::vector<P> boundary;
};

class MeshMaker {
 public:
  explicit MeshMaker(unsigned seed) : rng_(seed) {}

  // A star-shaped fan around a centre: every sector < 180 deg, so the triangles tile the polygon.
  Mesh2D fan() {
    const int k = pick(4, 12);
    const P c = maybe_on_centre({pick(20 * 256, 44 * 256), pick(20 * 256, 44 * 256)});
    const double turn = uniform(0, 2 * std::numbers::pi);
    Mesh2D m;
    for (int i = 0; i < k; ++i) {
      const double angle = turn + (i + uniform(-0.4, 0.4)) / k * 2 * std::numbers::pi;
      const double r = uniform(1.0, 12.0) * 256;
      m.boundary.push_back(maybe_on_centre({c.x + std::llround(r * std::cos(angle)), c.y + std::llround(r * std::sin(angle))}));
    }
    if (coin()) std::reverse(m.boundary.begin(), m.boundary.end());
    for (int i = 0; i < k; ++i) m.triangles.push_back({c, m.boundary[i], m.boundary[(i + 1) % k]});
    // Moving points onto pixel centres can fold a thin sector over its neighbour; such a fan is
    // not a valid closed mesh, so it is rejected (empty) rather than tested.
    int positive = 0, negative = 0;
    for (const auto& t : m.triangles) {
      const std::int64_t area = area2(t);
      positive += area > 0;
      negative += area < 0;
    }
    if (positive != k && negative != k) return {};
    return m;
  }

  // A jittered grid of quads, each split on a random diagonal. Empty if the jitter folded a quad.
  Mesh2D grid() {
    const int nx = pick(1, 6), ny = pick(1, 6);
    const double s = uniform(2.0, 6.0) * 256;
    const P o{pick(2 * 256, 6 * 256), pick(2 * 256, 6 * 256)};
    std::vector<P> pts;
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        pts.push_back(maybe_on_centre({o.x + std::llround((i + uniform(-0.2, 0.2)) * s),
                                       o.y + std::llround((j + uniform(-0.2, 0.2)) * s)}));
    auto at = [&](int i, int j) { return pts[static_cast<std::size_t>(j * (nx + 1) + i)]; };
    Mesh2D m;
    const bool flip = coin();
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const P a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        std::array<P, 3> t1 = {a, b, c}, t2 = {a, c, d};
        if (coin()) t1 = {a, b, d}, t2 = {b, c, d};
        for (auto* t : {&t1, &t2}) {
          if (area2(*t) <= 0) return {};  // folded or degenerate: not a valid closed mesh
          if (flip) std::swap((*t)[1], (*t)[2]);
          m.triangles.push_back(*t);
        }
      }
    }
    for (int i = 0; i < nx; ++i) m.boundary.push_back(at(i, 0));
    for (int j = 0; j < ny; ++j) m.boundary.push_back(at(nx, j));
    for (int i = nx; i > 0; --i) m.boundary.push_back(at(i, ny));
    for (int j = ny; j > 0; --j) m.boundary.push_back(at(0, j));
    return m;
  }

 private:
  std::int64_t pick(std::int64_t lo, std::int64_t hi) { return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng_); }
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool coin() { return (rng_() & 1) != 0; }
  // A quarter of the coordinates land exactly on pixel centres, where the fill rule decides.
  P maybe_on_centre(P p) {
    if (pick(0, 3) == 0) p.x = (p.x >> 8) * 256 + 128;
    if (pick(0, 3) == 0) p.y = (p.y >> 8) * 256 + 128;
    return p;
  }
  std::mt19937_64 rng_;
};

// 10^5 meshes in four shards of 25,000 (their own seeds), so that ctest can run them in parallel;
// each shard on the scalar rasterizer and on the SIMD kernels of each ISA.
struct WatertightParam {
  unsigned shard;
  std::optional<Isa> isa;  // none: the scalar rasterizer
};
class Watertight : public ::testing::TestWithParam<WatertightParam> {};

TEST_P(Watertight, RandomFansAndGridsCoverEveryInteriorPixelExactlyOnce) {
  const tile::simd::Kernels* kernels = nullptr;
  if (GetParam().isa) {
    if (!isa_supported(*GetParam().isa)) GTEST_SKIP() << "this CPU does not have " << to_string(*GetParam().isa);
    kernels = tile::simd_raster_kernels(*GetParam().isa);
  }
  MeshMaker maker(12345 + GetParam().shard);
  Coverage cov(64, 64, kernels);
  std::size_t meshes = 0, interior_checked = 0, failures = 0;
  while (meshes < 25000) {
    const Mesh2D m = meshes % 5 < 3 ? maker.fan() : maker.grid();
    if (m.triangles.empty()) continue;
    ++meshes;
    // Pixels outside the boundary's bounding box cannot be covered (the rasterizer never leaves a
    // triangle's bounds), so only the box, one pixel wider, is cleared and checked.
    std::int64_t lo_x = INT64_MAX, lo_y = INT64_MAX, hi_x = INT64_MIN, hi_y = INT64_MIN;
    for (const P& p : m.boundary) {
      lo_x = std::min(lo_x, p.x), lo_y = std::min(lo_y, p.y), hi_x = std::max(hi_x, p.x), hi_y = std::max(hi_y, p.y);
    }
    const int x0 = std::max<int>(0, int(lo_x / 256) - 1), y0 = std::max<int>(0, int(lo_y / 256) - 1);
    const int x1 = std::min<int>(cov.w() - 1, int(hi_x / 256) + 1), y1 = std::min<int>(cov.h() - 1, int(hi_y / 256) + 1);
    cov.clear(x0, y0, x1, y1);
    for (const auto& t : m.triangles) cov.add(t[0], t[1], t[2]);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const int n = cov.at(x, y);
        const std::optional<int> w = winding(m.boundary, centre_of(x, y));
        const bool bad = n > 1 || (w && ((*w != 0 && n != 1) || (*w == 0 && n != 0)));
        interior_checked += w && *w != 0 ? 1 : 0;
        if (bad && ++failures <= 5) {
          ADD_FAILURE() << "mesh " << meshes << ": pixel (" << x << ", " << y << ") covered " << n
                        << " times, winding " << (w ? std::to_string(*w) : "on boundary");
        }
      }
    }
  }
  EXPECT_EQ(failures, 0u);
  EXPECT_GT(interior_checked, 1'000'000u);
  std::printf("%zu meshes, %zu interior pixel centres checked, %zu failures\n", meshes, interior_checked, failures);
}

std::vector<WatertightParam> watertight_params() {
  std::vector<WatertightParam> v;
  for (std::optional<Isa> isa : {std::optional<Isa>{}, std::optional(Isa::sse2), std::optional(Isa::avx2),
                                 std::optional(Isa::avx512)}) {
    for (unsigned shard = 0; shard < 4; ++shard) v.push_back({shard, isa});
  }
  return v;
}

INSTANTIATE_TEST_SUITE_P(Shards, Watertight, ::testing::ValuesIn(watertight_params()),
                         [](const ::testing::TestParamInfo<WatertightParam>& p) {
                           return (p.param.isa ? std::string(to_string(*p.param.isa)) : std::string("scalar")) +
                                  "_" + std::to_string(p.param.shard);
                         });

// The merge in pieces (count, place, scatter: the parallel merge of a pass) makes the bins the
// serial merge makes, in range order within each bin, whatever order the ranges' pieces run in,
// and appends to bins that already hold entries.
TEST(Bins, MergeInPiecesMatchesTheSerialMerge) {
  std::mt19937 rng(11);
  for (int round = 0; round < 20; ++round) {
    const std::size_t tiles = 1 + rng() % 40, ranges = 1 + rng() % 30;
    std::vector<RangeBinning> binning(ranges + 3);  // spare ranges past the count are not merged
    for (auto& rb : binning) {
      const std::size_t entries = rng() % 200;
      for (std::size_t e = 0; e < entries; ++e) {
        rb.tile.push_back(static_cast<std::uint32_t>(rng() % tiles));
        rb.index.push_back(static_cast<std::uint32_t>(rng() & kIndexMask));
      }
      rb.counts.drawn = rng() % 100;
      rb.counts.bin_entries = entries;
    }
    std::vector<std::vector<std::uint32_t>> serial(tiles), pieces(tiles);
    for (std::size_t t = 0; t < tiles; t += 3) serial[t] = pieces[t] = {0xdeadbeefu, static_cast<std::uint32_t>(t)};
    FrameStats serial_stats, pieces_stats;
    merge_ranges(binning, ranges, serial, serial_stats);
    std::vector<std::uint32_t> offsets(ranges * tiles, 0x5a5a5a5au);
    std::vector<std::size_t> order(ranges);
    for (std::size_t r = 0; r < ranges; ++r) order[r] = r;
    auto row = [&](std::size_t r) { return std::span<std::uint32_t>(offsets.data() + r * tiles, tiles); };
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t r : order) count_range(binning[r], row(r));
    place_ranges(binning, ranges, offsets, pieces, pieces_stats);
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t r : order) scatter_range(binning[r], r, row(r), pieces);
    EXPECT_EQ(pieces, serial) << "round " << round;
    EXPECT_EQ(pieces_stats.triangles_drawn, serial_stats.triangles_drawn);
    EXPECT_EQ(pieces_stats.bin_entries, serial_stats.bin_entries);
  }
}

}  // namespace
}  // namespace facet::raster
