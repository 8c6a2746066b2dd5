#include "shadow/volume.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <span>
#include <unordered_map>

#include <Eigen/Geometry>

#include "geometry/project.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::shadow {

// ---- adjacency ----

void MeshEdges::build(const Mesh& mesh) {
  const std::size_t n = mesh.positions.size();
  // Weld: a vertex within kWeld of the mesh's extent (per coordinate) of an earlier vertex is that
  // vertex (seams and creases split vertices whose positions agree only to rounding). A hash grid
  // of cells 2 kWeld wide: a vertex's neighbourhood overlaps at most two cells per axis.
  double extent = 0.0;
  for (const Vec3& p : mesh.positions) {
    if (p.allFinite()) extent = std::max(extent, double(p.cwiseAbs().maxCoeff()));
  }
  const double eps = extent * kWeld, cell = 2.0 * eps;
  weld.resize(n);
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  grid.reserve(n);
  auto cell_key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (std::uint64_t(x) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full) ^
           (std::uint64_t(z) * 0x165667B19E3779F9ull);
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3& p = mesh.positions[i];
    weld[i] = i;
    if (!p.allFinite() || !(cell > 0.0) || extent > 1e30) continue;  // welded only to bit-identical copies (below)
    std::int64_t lo[3], hi[3];
    for (int c = 0; c < 3; ++c) {
      lo[c] = static_cast<std::int64_t>(std::floor((p[c] - eps) / cell));
      hi[c] = static_cast<std::int64_t>(std::floor((p[c] + eps) / cell));
    }
    bool found = false;
    for (std::int64_t x = lo[0]; x <= hi[0] && !found; ++x) {
      for (std::int64_t y = lo[1]; y <= hi[1] && !found; ++y) {
        for (std::int64_t z = lo[2]; z <= hi[2] && !found; ++z) {
          const auto it = grid.find(cell_key(x, y, z));
          if (it == grid.end()) continue;
          for (const std::uint32_t r : it->second) {
            if ((mesh.positions[r] - p).cwiseAbs().maxCoeff() <= eps) {
              weld[i] = r;
              found = true;
              break;
            }
          }
        }
      }
    }
    if (!found) {
      grid[cell_key(static_cast<std::int64_t>(std::floor(p[0] / cell)), static_cast<std::int64_t>(std::floor(p[1] / cell)),
                    static_cast<std::int64_t>(std::floor(p[2] / cell)))]
          .push_back(i);
    }
  }
  // Each triangle's three edges between welded vertices, as (low, high, triangle * 2 + reversed).
  std::vector<std::array<std::uint32_t, 3>> uses;
  uses.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const std::uint32_t w[3] = {weld[tri[0]], weld[tri[1]], weld[tri[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;  // degenerate: casts nothing
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = w[k], b = w[(k + 1) % 3], code = static_cast<std::uint32_t>(t) * 2;
      uses.push_back(a < b ? std::array<std::uint32_t, 3>{a, b, code} : std::array<std::uint32_t, 3>{b, a, code + 1});
    }
  }
  std::sort(uses.begin(), uses.end());
  edges.clear();
  first.clear();
  incident.clear();
  incident.reserve(uses.size());
  closed = !uses.empty();
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    int balance = 0;
    edges.push_back({uses[i][0], uses[i][1]});
    first.push_back(static_cast<std::uint32_t>(incident.size()));
    for (; j < uses.size() && uses[j][0] == uses[i][0] && uses[j][1] == uses[i][1]; ++j) {
      incident.push_back(uses[j][2]);
      balance += (uses[j][2] & 1) ? -1 : 1;
    }
    if (balance != 0) closed = false;
    i = j;
  }
  first.push_back(static_cast<std::uint32_t>(incident.size()));
  positions = mesh.positions;
  triangles = mesh.triangles;
}

bool MeshEdges::built_from(const Mesh& mesh) const {
  return first.size() > 0 && positions.size() == mesh.positions.size() && triangles.size() == mesh.triangles.size() &&
         std::memcmp(positions.data(), mesh.positions.data(), positions.size() * sizeof(Vec3)) == 0 &&
         std::memcmp(triangles.data(), mesh.triangles.data(), triangles.size() * sizeof triangles[0]) == 0;
}

// ---- frame ----

void ShadowVolumes::plan(const Scene& scene, int width, int height) {
  lights_.clear();
  mask_of_.assign(scene.lights.size(), -1);
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const Light& light = scene.lights[l];
    if (!light.enabled || light.shadow.method != ShadowMethod::volume) continue;
    mask_of_[l] = static_cast<int>(lights_.size());
    lights_.push_back(l);
  }
  volume_triangles_ = 0;
  if (lights_.empty()) return;
  if (width != width_ || height != height_) dirty_tile_size_ = 0;  // every tile dirty again
  width_ = width, height_ = height;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  depth_.resize(pixels, 1.0f);
  masks_.resize(pixels * lights_.size());
}

DepthView ShadowVolumes::depth_view() {
  DepthView v;
  v.data = depth_.data();
  v.width = width_;
  v.height = height_;
  v.stride_bytes = static_cast<std::size_t>(width_) * sizeof(float);
  v.y_up = false;
  return v;
}

std::uint8_t* ShadowVolumes::dirty_tiles(int tile_size) {
  const std::size_t tiles = static_cast<std::size_t>((width_ + tile_size - 1) / tile_size) *
                            static_cast<std::size_t>((height_ + tile_size - 1) / tile_size);
  if (tile_size != dirty_tile_size_ || dirty_.size() != tiles) dirty_.assign(tiles, 1);
  dirty_tile_size_ = tile_size;
  return dirty_.data();
}

bool ShadowVolumes::has(std::size_t light) const { return light < mask_of_.size() && mask_of_[light] >= 0; }

std::uint64_t ShadowVolumes::bytes(int width, int height, std::size_t lights, std::size_t casters) {
  if (lights == 0) return 0;
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
  // Depth, masks, a band's counts per thread (small); caps and sides: about two faces per caster
  // triangle; adjacency: three uses and a copy of the mesh per triangle.
  return pixels * (4 + lights) + std::uint64_t(casters) * (2 * sizeof(VolumeTriangle) + 3 * 12 + 12 + 36);
}

namespace {

using V4 = Eigen::Vector4d;

// Signed distances to the planes a volume is clipped by: near, and the guard band's four sides
// (never far: a volume reaches infinity, whose points lie just beyond the far plane).
inline double plane_distance(const V4& v, int plane, double gx, double gy) {
  switch (plane) {
    case 0: return v.z() + v.w();
    case 1: return gx * v.w() + v.x();
    case 2: return gx * v.w() - v.x();
    case 3: return gy * v.w() + v.y();
    default: return gy * v.w() - v.y();
  }
}

// Sutherland-Hodgman against the five planes; an edge is cut from its inside end towards its
// outside end, so an edge shared by two faces is cut at the same point in both.
int clip_polygon(ShadowVolumes::ClipVert* poly, int n, double gx, double gy) {
  ShadowVolumes::ClipVert tmp[16];
  for (int plane = 0; plane < 5 && n > 0; ++plane) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const ShadowVolumes::ClipVert& a = poly[i];
      const ShadowVolumes::ClipVert& b = poly[(i + 1) % n];
      const double da = plane_distance(a.clip, plane, gx, gy), db = plane_distance(b.clip, plane, gx, gy);
      const bool ina = da >= 0.0, inb = db >= 0.0;
      if (ina && m < 16) tmp[m++] = a;
      if (ina != inb && m < 16) {
        ShadowVolumes::ClipVert& cut = tmp[m++];
        cut.snapped = false;
        cut.clip = ina ? V4(a.clip + (b.clip - a.clip) * (da / (da - db))) : V4(b.clip + (a.clip - b.clip) * (db / (db - da)));
      }
    }
    n = m;
    std::copy(tmp, tmp + m, poly);
  }
  return n;
}

}  // namespace

void ShadowVolumes::emit(std::uint32_t ia, std::uint32_t ib, std::uint32_t ic, bool side) {
  ClipVert poly[16] = {verts_[ia], verts_[ib], verts_[ic]};
  const double g = raster::kGuardBandPixels;
  bool inside = true;  // most faces need no clipping
  for (int i = 0; i < 3 && inside; ++i) {
    for (int plane = 0; plane < 5 && inside; ++plane) inside = plane_distance(poly[i].clip, plane, guard_x_, guard_y_) >= 0.0;
  }
  const int n = inside ? 3 : clip_polygon(poly, 3, guard_x_, guard_y_);
  if (n < 3) return;
  std::int32_t sx[16], sy[16];
  double sz[16];
  const double half_w = 0.5 * width_, half_h = 0.5 * height_;
  for (int i = 0; i < n; ++i) {
    const V4& v = poly[i].clip;
    if (!(v.w() > 0.0) || !v.allFinite()) return;  // only a degenerate volume (a point at infinity seen head on)
    const double inv_w = 1.0 / v.w();
    sz[i] = 0.5 * v.z() * inv_w + 0.5;  // unclamped: points at infinity lie just beyond 1
    if (!std::isfinite(sz[i])) return;
    if (poly[i].snapped) {  // a caster vertex as the camera's pass placed it
      sx[i] = poly[i].x, sy[i] = poly[i].y;
      continue;
    }
    const double x = std::clamp((v.x() * inv_w + 1.0) * half_w, -g, g), y = std::clamp((1.0 - v.y() * inv_w) * half_h, -g, g);
    sx[i] = static_cast<std::int32_t>(std::nearbyint(x * raster::kSubpixelOne));
    sy[i] = static_cast<std::int32_t>(std::nearbyint(y * raster::kSubpixelOne));
  }
  for (int i = 1; i + 1 < n; ++i) {  // a fan; inner edges share their snapped ends
    VolumeTriangle t;
    const int k[3] = {0, i, i + 1};
    for (int j = 0; j < 3; ++j) t.x[j] = sx[k[j]], t.y[j] = sy[k[j]], t.z[j] = sz[k[j]];
    const std::int64_t area = raster::signed_area2(t.x[0], t.y[0], t.x[1], t.y[1], t.x[2], t.y[2]);
    if (area == 0) continue;
    // area < 0: counter-clockwise as the camera sees it (the y-down screen flips the sign), so
    // the face's outward side faces the camera.
    t.sign = static_cast<std::int8_t>(area < 0 ? -1 : 1);
    t.side = side;
    if (area < 0) {
      std::swap(t.x[1], t.x[2]);
      std::swap(t.y[1], t.y[2]);
      std::swap(t.z[1], t.z[2]);
    }
    raster::ScreenTriangle st;
    for (int j = 0; j < 3; ++j) st.x[j] = t.x[j], st.y[j] = t.y[j];
    if (!raster::finish_setup(st, width_, height_)) continue;
    t.min_px = st.min_px, t.max_px = st.max_px, t.min_py = st.min_py, t.max_py = st.max_py;
    for (int j = 0; j < 3; ++j) t.bias[j] = st.bias[j];
    t.inv_area2 = 1.0 / static_cast<double>(area < 0 ? -area : area);
    triangles_.push_back(t);
  }
}

void ShadowVolumes::build_light(const Scene& scene, const Light& light, const Eigen::Matrix4d& view) {
  triangles_.clear();
  const bool directional = light.type == LightType::directional;
  Eigen::Vector3d at = Eigen::Vector3d::Zero(), travel = Eigen::Vector3d::Zero();
  if (directional) {
    travel = view.topLeftCorner<3, 3>() * light.direction.cast<double>();
  } else {
    at = (view * light.position.cast<double>().homogeneous()).head<3>();
  }
  if (edges_.size() < scene.meshes.size()) edges_.resize(scene.meshes.size());
  for (const Instance& inst : scene.objects) {
    if (!inst.cast_shadows) continue;
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    if (mesh.triangles.empty()) continue;
    MeshEdges& me = edges_[inst.mesh];
    if (!me.built_from(mesh)) me.build(mesh);
    const Eigen::Matrix4d mv = view * inst.model.cast<double>();
    const std::size_t n = mesh.positions.size();
    eye_.resize(n);
    verts_.resize(n + (directional ? 1 : n));  // the vertices, then their points at infinity
    // Caster vertices in clip space and on screen exactly as the camera's pass places them (the
    // same float transform and snapping), so a visible surface and its cap share their pixels'
    // coverage and (to rounding) their depth.
    clip_.resize(n);
    screen_.resize(n);
    geometry::transform_vertices(geometry::to_rows(projection_ * mv), mesh.positions.data(), 0, n, planes_,
                                 geometry::Viewport{width_, height_}, clip_.data(), screen_.data());
    for (std::size_t i = 0; i < n; ++i) {
      eye_[i] = mv * mesh.positions[i].cast<double>().homogeneous();
      ClipVert& c = verts_[i];
      c.clip = V4(clip_[i][0], clip_[i][1], clip_[i][2], clip_[i][3]);
      c.snapped = screen_[i].projected;
      c.x = screen_[i].x, c.y = screen_[i].y;
      if (directional && i > 0) continue;
      const Eigen::Vector3d away = directional ? travel : Eigen::Vector3d(eye_[i].head<3>() - at);
      ClipVert& f = verts_[n + i];
      f.clip = projection_ * V4(away.x(), away.y(), away.z(), 0.0);
      f.snapped = false;
    }
    const auto far = [&](std::uint32_t v) { return static_cast<std::uint32_t>(n) + (directional ? 0u : v); };
    // Which side of each triangle the light sees: +1 its front, -1 its back, 0 edge-on (or not finite).
    facing_.resize(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3d a = eye_[tri[0]].head<3>(), b = eye_[tri[1]].head<3>(), c = eye_[tri[2]].head<3>();
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      const double d = normal.dot(directional ? Eigen::Vector3d(-travel) : Eigen::Vector3d(at - a));
      const bool degenerate = me.weld[tri[0]] == me.weld[tri[1]] || me.weld[tri[1]] == me.weld[tri[2]] ||
                              me.weld[tri[2]] == me.weld[tri[0]];
      facing_[t] = degenerate ? 0 : d > 0.0 ? 1 : d < 0.0 ? -1 : 0;
    }
    // A closed mesh casts from its triangles facing away from the light, turned towards it (weight
    // -1 reverses a triangle): the same silhouette as its lit side's, but its dark side is then
    // the volume's front cap, so no surface of the mesh lies inside its own volume (where smooth
    // normals light a face that looks away from the light, the lighting decides, as ray-cast
    // shadows' normal offset does), while whatever lies behind it from the light does. An open
    // mesh casts from every triangle, each turned towards the light.
    auto weight = [&](std::size_t t) -> int { return me.closed ? (facing_[t] < 0 ? -1 : 0) : facing_[t]; };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const int w = weight(t);
      if (w == 0) continue;
      std::uint32_t i0 = me.weld[mesh.triangles[t][0]], i1 = me.weld[mesh.triangles[t][1]], i2 = me.weld[mesh.triangles[t][2]];
      if (w < 0) std::swap(i1, i2);
      emit(i0, i1, i2, false);                                   // front cap: outwards = towards the light
      if (!directional) emit(far(i0), far(i2), far(i1), false);  // back cap at infinity, reversed
    }
    // The boundary of the weighted set: per edge, the sum of its uses' orientations.
    for (std::size_t e = 0; e < me.edges.size(); ++e) {
      int net = 0;
      for (std::uint32_t k = me.first[e]; k < me.first[e + 1]; ++k) {
        const std::uint32_t use = me.incident[k];
        net += weight(use >> 1) * ((use & 1) ? -1 : 1);
      }
      if (net == 0) continue;
      const std::uint32_t u = net > 0 ? me.edges[e][0] : me.edges[e][1], v = net > 0 ? me.edges[e][1] : me.edges[e][0];
      for (int k = std::abs(net); k > 0; --k) {  // the quad u, v, v at infinity, u at infinity, outwards
        emit(u, far(u), v, true);
        if (!directional) emit(v, far(u), far(v), true);
      }
    }
  }
  volume_triangles_ += triangles_.size();
}

void ShadowVolumes::rasterize(std::uint8_t* mask, parallel::Arena& arena) {
  constexpr int kBand = 16;
  const int bands = (height_ + kBand - 1) / kBand;
  band_first_.assign(static_cast<std::size_t>(bands) + 1, 0);
  for (const VolumeTriangle& t : triangles_) {
    for (int b = t.min_py / kBand; b <= t.max_py / kBand; ++b) ++band_first_[static_cast<std::size_t>(b) + 1];
  }
  std::partial_sum(band_first_.begin(), band_first_.end(), band_first_.begin());
  band_list_.resize(band_first_.back());
  band_cursor_.assign(band_first_.begin(), band_first_.end() - 1);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    const VolumeTriangle& t = triangles_[i];
    for (int b = t.min_py / kBand; b <= t.max_py / kBand; ++b) {
      band_list_[band_cursor_[static_cast<std::size_t>(b)]++] = static_cast<std::uint32_t>(i);
    }
  }
  const int width = width_, height = height_;
  const float* depth = depth_.data();
  const std::size_t band_pixels = static_cast<std::size_t>(kBand) * static_cast<std::size_t>(width);
  if (counts_.size() < static_cast<std::size_t>(arena.threads()) * band_pixels) {
    counts_.resize(static_cast<std::size_t>(arena.threads()) * band_pixels);
  }
  arena.parallel_for(tbb::blocked_range<int>(0, bands), [&](const tbb::blocked_range<int>& r, int slot) {
    const std::span<std::int32_t> counts(counts_.data() + static_cast<std::size_t>(slot) * band_pixels, band_pixels);
    for (int b = r.begin(); b != r.end(); ++b) {
      const int y0 = b * kBand, y1 = std::min(height, y0 + kBand) - 1;
      std::fill(counts.begin(), counts.end(), 0);
      for (std::uint32_t entry = band_first_[static_cast<std::size_t>(b)]; entry < band_first_[static_cast<std::size_t>(b) + 1]; ++entry) {
        const VolumeTriangle& t = triangles_[band_list_[entry]];
        const int r0 = std::max(t.min_py, y0), r1 = std::min(t.max_py, y1);
        if (r0 > r1) continue;
        const double inv_area = t.inv_area2;
        // Spans: per row, the pixels whose biased edge values are all >= 0 (the edge values are
        // those of raster::for_each_covered_pixel, so coverage is the raster's top-left rule);
        // found by exact integer division on wide triangles, pixel by pixel on narrow ones.
        std::int64_t row_e[3], step_x[3], step_y[3];
        double dzx = 0.0;
        const std::int64_t px = std::int64_t(t.min_px) * raster::kSubpixelOne + raster::kPixelCentre;
        const std::int64_t py = std::int64_t(r0) * raster::kSubpixelOne + raster::kPixelCentre;
        for (int k = 0; k < 3; ++k) {
          const raster::Edge e = raster::edge_at(t.x, t.y, t.bias, k, px, py);
          row_e[k] = e.at;
          step_x[k] = e.A * raster::kSubpixelOne;
          step_y[k] = e.B * raster::kSubpixelOne;
          dzx += static_cast<double>(step_x[k]) * t.z[k];
        }
        dzx *= inv_area;
        const std::int64_t last = t.max_px - t.min_px;
        const bool narrow = last < 8;
        for (int y = r0; y <= r1; ++y, row_e[0] += step_y[0], row_e[1] += step_y[1], row_e[2] += step_y[2]) {
          std::int64_t lo = 0, hi = last;
          if (narrow) {  // the first and last covered pixel by stepping
            std::int64_t e0 = row_e[0], e1 = row_e[1], e2 = row_e[2];
            while (lo <= last && (e0 | e1 | e2) < 0) ++lo, e0 += step_x[0], e1 += step_x[1], e2 += step_x[2];
            hi = lo - 1;
            while (hi < last && (e0 | e1 | e2) >= 0) ++hi, e0 += step_x[0], e1 += step_x[1], e2 += step_x[2];
          } else {
            for (int k = 0; k < 3; ++k) {
              if (step_x[k] > 0) {
                lo = std::max(lo, -raster::floor_div(row_e[k], step_x[k]));
              } else if (step_x[k] < 0) {
                hi = std::min(hi, raster::floor_div(row_e[k], -step_x[k]));
              } else if (row_e[k] < 0) {
                hi = -1;
              }
            }
          }
          if (lo > hi) continue;
          // Depth at the span's first pixel from the unbiased edge values (barycentrics), then
          // stepped: |error| stays near 1e-16 per step, far below kDepthTolerance.
          double z_lo = 0.0;
          for (int k = 0; k < 3; ++k) z_lo += static_cast<double>(row_e[k] + step_x[k] * lo - t.bias[k]) * t.z[k];
          z_lo *= inv_area;
          const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(t.min_px);
          const float* d = depth + row;
          std::int32_t* c = counts.data() + static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width) + static_cast<std::size_t>(t.min_px);
          const int sign = t.sign;
          const double tie = (sign < 0) != t.side ? -kDepthTolerance : kDepthTolerance;  // see the header: ties
          for (std::int64_t i = lo; i <= hi; ++i) {
            const double z = z_lo + static_cast<double>(i - lo) * dzx;
            c[i] += z >= static_cast<double>(d[i]) + tie ? sign : 0;
          }
        }
      }
      for (int y = y0; y <= y1; ++y) {
        const std::int32_t* c = counts.data() + static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width);
        std::uint8_t* out = mask + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
        for (int x = 0; x < width; ++x) out[x] = c[x] == 0 ? 1 : 0;
      }
    }
  });
}

void ShadowVolumes::build(const Scene& scene, const Eigen::Matrix4d& view, const Eigen::Matrix4d& projection,
                          parallel::Arena& arena) {
  projection_ = projection;
  planes_ = geometry::guard_band_planes(geometry::Viewport{width_, height_});
  guard_x_ = planes_.guard_x, guard_y_ = planes_.guard_y;
  volume_triangles_ = 0;
  const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  for (std::size_t i = 0; i < lights_.size(); ++i) {
    build_light(scene, scene.lights[lights_[i]], view);
    rasterize(masks_.data() + i * pixels, arena);
  }
}

void ShadowVolumes::visibility(std::size_t light, std::size_t count, const float* px, const float* py, const float* pz,
                               std::size_t stride, float* visible) const {
  const std::uint8_t* mask = masks_.data() + static_cast<std::size_t>(mask_of_[light]) * static_cast<std::size_t>(width_) *
                                                 static_cast<std::size_t>(height_);
  const Eigen::Matrix4d& P = projection_;
  for (std::size_t i = 0; i < count; ++i) {
    const double x = px[i * stride], y = py[i * stride], z = pz[i * stride];
    const double cx = P(0, 0) * x + P(0, 1) * y + P(0, 2) * z + P(0, 3);
    const double cy = P(1, 0) * x + P(1, 1) * y + P(1, 2) * z + P(1, 3);
    const double cw = P(3, 0) * x + P(3, 1) * y + P(3, 2) * z + P(3, 3);
    visible[i] = 1.0f;
    if (!(cw > 0.0)) continue;
    const double sx = (cx / cw + 1.0) * 0.5 * width_, sy = (1.0 - cy / cw) * 0.5 * height_;
    if (!(sx >= 0.0 && sx < width_ && sy >= 0.0 && sy < height_)) continue;
    visible[i] = mask[static_cast<std::size_t>(sy) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(sx)];
  }
}

}  // namespace facet::shadow
