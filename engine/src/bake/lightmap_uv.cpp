// Lightmap charts and their atlas (facet/lightmap.hpp). Charts grow from seed triangles (in
// triangle order, so the result is deterministic) across edges shared by exactly two triangles,
// taking a neighbour whose normal is within the chart angle of the seed's and whose projection on
// the seed's plane overlaps none of the chart's triangles; each chart is laid flat by that
// projection, and the charts' rectangles are packed into shelves.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <new>
#include <numbers>
#include <string>
#include <unordered_map>

#include "common/format.hpp"
#include "common/try.hpp"
#include "facet/lightmap.hpp"

namespace facet {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

// Interiors of two triangles (counter-clockwise) overlap: no edge normal of either separates
// them by more than `eps`. Triangles that only share an edge or a vertex do not overlap.
bool interiors_overlap(const std::array<V2, 3>& a, const std::array<V2, 3>& b, double eps) {
  auto separated_by_edges_of = [&](const std::array<V2, 3>& p, const std::array<V2, 3>& q) {
    for (int k = 0; k < 3; ++k) {
      const V2 e = p[(k + 1) % 3] - p[k];
      const V2 n(e.y(), -e.x());  // outward for a counter-clockwise triangle
      const double edge = n.dot(p[k]);
      double q_min = std::numeric_limits<double>::infinity();
      for (const V2& v : q) q_min = std::min(q_min, n.dot(v));
      if (q_min >= edge - eps * n.norm()) return true;  // q lies on the outer side of this edge
    }
    return false;
  };
  return !separated_by_edges_of(a, b) && !separated_by_edges_of(b, a);
}

// The chart being grown: its projected triangles in a uniform grid (cells about the seed's size;
// a triangle spanning more than kMaxCells cells goes to a list every candidate is tested against).
class ChartGrid {
 public:
  static constexpr long long kMaxCells = 64;
  void reset(double cell) {
    cell_ = cell;
    cells_.clear();
    large_.clear();
    tris_.clear();
  }
  bool overlaps(const std::array<V2, 3>& t, double eps) const {
    for (std::uint32_t i : large_)
      if (interiors_overlap(tris_[i], t, eps)) return true;
    bool hit = false;
    for_cells(t, [&](std::uint64_t key) {
      if (hit) return;
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (std::uint32_t i : it->second) {
        if (interiors_overlap(tris_[i], t, eps)) {
          hit = true;
          return;
        }
      }
    });
    return hit;
  }
  void add(const std::array<V2, 3>& t) {
    const auto index = static_cast<std::uint32_t>(tris_.size());
    tris_.push_back(t);
    if (!for_cells(t, [&](std::uint64_t key) { cells_[key].push_back(index); })) large_.push_back(index);
  }

 private:
  // Calls fn for each cell the triangle's box touches; false (and no call) if more than kMaxCells.
  template <class Fn>
  bool for_cells(const std::array<V2, 3>& t, const Fn& fn) const {
    const V2 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]), hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
    const double x0 = std::floor(lo.x() / cell_), x1 = std::floor(hi.x() / cell_);
    const double y0 = std::floor(lo.y() / cell_), y1 = std::floor(hi.y() / cell_);
    if (!((x1 - x0 + 1) * (y1 - y0 + 1) <= static_cast<double>(kMaxCells))) return false;
    for (double y = y0; y <= y1; ++y)
      for (double x = x0; x <= x1; ++x) {
        const auto ix = static_cast<std::uint32_t>(static_cast<std::int64_t>(x));
        const auto iy = static_cast<std::uint32_t>(static_cast<std::int64_t>(y));
        fn((std::uint64_t{ix} << 32) | iy);
      }
    return true;
  }
  double cell_ = 1;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
  std::vector<std::uint32_t> large_;
  std::vector<std::array<V2, 3>> tris_;
};

struct ChartBuild {
  V3 t, b;             // the plane's axes (t x b = the seed's normal)
  V2 lo, hi;           // projected bounds, in units of length
  bool degenerate = false;
};

Status check_options(const LightmapUvOptions& o) {
  auto bad = [](const char* field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, field, std::string(field) + ": " + what};
  };
  if (!(std::isfinite(o.texels_per_unit) && o.texels_per_unit > 0)) {
    return bad("texels_per_unit", "expected a finite number > 0, found " + format_number(o.texels_per_unit));
  }
  if (o.padding < 1 || o.padding > 64) return bad("padding", "expected 1 to 64 texels, found " + std::to_string(o.padding));
  if (!(o.chart_angle_deg > 0 && o.chart_angle_deg < 90)) {
    return bad("chart_angle_deg", "expected an angle in (0, 90) degrees, found " + format_number(o.chart_angle_deg));
  }
  if (o.max_size < 1 || o.max_size > 65536) {
    return bad("max_size", "expected 1 to 65536 texels, found " + std::to_string(o.max_size));
  }
  return {};
}

Result<LightmapUnwrap> unwrap(const Mesh& mesh, const LightmapUvOptions& o) {
  const std::size_t tri_count = mesh.triangles.size();
  const double density = o.texels_per_unit, cos_limit = std::cos(o.chart_angle_deg * std::numbers::pi / 180.0);

  // Face normals in double; a triangle with a non-finite corner or no area is degenerate.
  std::vector<V3> normal(tri_count);
  std::vector<std::uint8_t> degenerate(tri_count);
  auto corner = [&](std::size_t t, int k) { return mesh.positions[mesh.triangles[t][static_cast<std::size_t>(k)]].cast<double>(); };
  for (std::size_t t = 0; t < tri_count; ++t) {
    const V3 a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
    const V3 n = (b - a).cross(c - a);
    const double len = n.norm();
    degenerate[t] = !(std::isfinite(len) && len > 0);
    normal[t] = degenerate[t] ? V3::Zero() : V3(n / len);
  }

  // Positions welded by their bits; edges between welded vertices, with the triangles on them.
  std::unordered_map<std::uint64_t, std::uint32_t> weld_of;
  std::vector<std::uint32_t> weld(mesh.positions.size());
  {
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> buckets;  // hash collisions resolved below
    std::vector<std::uint32_t> representative;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3& p = mesh.positions[v];
      const std::uint64_t h = (std::uint64_t{std::bit_cast<std::uint32_t>(p.x())} * 0x9E3779B97F4A7C15ull) ^
                              (std::uint64_t{std::bit_cast<std::uint32_t>(p.y())} * 0xC2B2AE3D27D4EB4Full) ^
                              std::bit_cast<std::uint32_t>(p.z());
      auto& list = buckets[h];
      std::uint32_t id = std::numeric_limits<std::uint32_t>::max();
      for (std::uint32_t r : list) {
        const Vec3& q = mesh.positions[representative[r]];
        if (std::bit_cast<std::uint32_t>(q.x()) == std::bit_cast<std::uint32_t>(p.x()) &&
            std::bit_cast<std::uint32_t>(q.y()) == std::bit_cast<std::uint32_t>(p.y()) &&
            std::bit_cast<std::uint32_t>(q.z()) == std::bit_cast<std::uint32_t>(p.z())) {
          id = r;
          break;
        }
      }
      if (id == std::numeric_limits<std::uint32_t>::max()) {
        id = static_cast<std::uint32_t>(representative.size());
        representative.push_back(static_cast<std::uint32_t>(v));
        list.push_back(id);
      }
      weld[v] = id;
    }
  }
  std::unordered_map<std::uint64_t, std::array<std::uint32_t, 3>> edges;  // {count, first, second}
  auto edge_key = [&](std::size_t t, int k) {
    std::uint32_t a = weld[mesh.triangles[t][static_cast<std::size_t>(k)]];
    std::uint32_t b = weld[mesh.triangles[t][static_cast<std::size_t>((k + 1) % 3)]];
    if (a > b) std::swap(a, b);
    return (std::uint64_t{a} << 32) | b;
  };
  for (std::size_t t = 0; t < tri_count; ++t) {
    if (degenerate[t]) continue;
    for (int k = 0; k < 3; ++k) {
      auto& e = edges[edge_key(t, k)];
      if (e[0] < 2) e[1 + e[0]] = static_cast<std::uint32_t>(t);
      ++e[0];
    }
  }

  // Charts, grown from seeds in triangle order.
  constexpr auto kNone = std::numeric_limits<std::uint32_t>::max();
  LightmapUnwrap out;
  out.chart_of_triangle.assign(tri_count, kNone);
  std::vector<ChartBuild> charts;
  ChartGrid grid;
  std::vector<std::uint32_t> queue;
  std::uint32_t degenerate_chart = kNone;
  auto project = [&](const ChartBuild& c, std::size_t t) {
    std::array<V2, 3> p;
    for (int k = 0; k < 3; ++k) {
      const V3 v = corner(t, k);
      p[static_cast<std::size_t>(k)] = V2(v.dot(c.t), v.dot(c.b));
    }
    return p;
  };
  for (std::size_t seed = 0; seed < tri_count; ++seed) {
    if (out.chart_of_triangle[seed] != kNone) continue;
    if (degenerate[seed]) {
      if (degenerate_chart == kNone) {
        degenerate_chart = static_cast<std::uint32_t>(charts.size());
        ChartBuild c;
        c.degenerate = true;
        c.lo = c.hi = V2::Zero();
        charts.push_back(c);
      }
      out.chart_of_triangle[seed] = degenerate_chart;
      continue;
    }
    const auto id = static_cast<std::uint32_t>(charts.size());
    ChartBuild c;
    const V3& n = normal[seed];
    const V3 axis = std::abs(n.x()) <= std::abs(n.y()) && std::abs(n.x()) <= std::abs(n.z()) ? V3::UnitX()
                    : std::abs(n.y()) <= std::abs(n.z())                                      ? V3::UnitY()
                                                                                               : V3::UnitZ();
    c.t = axis.cross(n).normalized();
    c.b = n.cross(c.t);
    const std::array<V2, 3> first = project(c, seed);
    const V2 lo = first[0].cwiseMin(first[1]).cwiseMin(first[2]), hi = first[0].cwiseMax(first[1]).cwiseMax(first[2]);
    const double size = (hi - lo).maxCoeff();
    grid.reset(2 * size);
    grid.add(first);
    c.lo = lo, c.hi = hi;
    out.chart_of_triangle[seed] = id;
    queue.assign(1, static_cast<std::uint32_t>(seed));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      for (int k = 0; k < 3; ++k) {
        const auto& e = edges[edge_key(t, k)];
        if (e[0] != 2) continue;  // a border or a non-manifold edge: charts do not grow across it
        const std::uint32_t next = e[1] == t ? e[2] : e[1];
        if (out.chart_of_triangle[next] != kNone || normal[next].dot(n) < cos_limit) continue;
        const std::array<V2, 3> p = project(c, next);
        const V2 plo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), phi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
        const double eps = 1e-9 * std::max({(phi - plo).maxCoeff(), size, 1e-30});
        if (grid.overlaps(p, eps)) continue;
        grid.add(p);
        c.lo = c.lo.cwiseMin(plo), c.hi = c.hi.cwiseMax(phi);
        out.chart_of_triangle[next] = id;
        queue.push_back(next);
      }
    }
    charts.push_back(c);
  }

  // Each chart's texel rectangle: its extent at the density, plus one texel so that every
  // corner, put half a texel in from the rectangle's edge, lies on a texel centre or inside.
  // Packed in shelves: charts by height (then width, then index), left to right; the atlas as wide
  // as a square of the charts' area, widened until it is also no taller than max_size. Returns
  // false, before any packing, when the charts' widest side or total area cannot fit.
  out.charts.resize(charts.size());
  std::vector<std::uint32_t> order(charts.size());
  auto pack = [&](double at) {
    double area = 0, widest = 0;
    for (const ChartBuild& c : charts) {
      const V2 ext = (c.hi - c.lo) * at;
      const double w = std::ceil(ext.x()) + 1, h = std::ceil(ext.y()) + 1;
      widest = std::max({widest, w, h});
      area += (w + o.padding) * (h + o.padding);
    }
    const double side = std::sqrt(area);
    if (!(widest + 2 * o.padding <= o.max_size && side + o.padding <= o.max_size)) return false;
    for (std::size_t i = 0; i < charts.size(); ++i) {
      const V2 ext = (charts[i].hi - charts[i].lo) * at;
      out.charts[i].w = static_cast<int>(std::ceil(ext.x())) + 1;
      out.charts[i].h = static_cast<int>(std::ceil(ext.y())) + 1;
      order[i] = static_cast<std::uint32_t>(i);
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      const auto& ca = out.charts[a];
      const auto& cb = out.charts[b];
      if (ca.h != cb.h) return ca.h > cb.h;
      if (ca.w != cb.w) return ca.w > cb.w;
      return a < b;
    });
    int width = static_cast<int>(std::max(std::ceil(side), widest)) + o.padding;
    for (;;) {
      width = std::min(width, o.max_size);
      int x = o.padding, y = o.padding, shelf = 0;
      for (std::uint32_t i : order) {
        auto& c = out.charts[i];
        if (x + c.w + o.padding > width) x = o.padding, y += shelf + o.padding, shelf = 0;
        c.x0 = x, c.y0 = y;
        x += c.w + o.padding;
        shelf = std::max(shelf, c.h);
        if (y + shelf + o.padding > o.max_size) break;
      }
      const int height = y + shelf + o.padding;
      if (height <= o.max_size) {
        out.width = width, out.height = height;
        return true;
      }
      if (width == o.max_size) return false;
      width += std::max(1, width / 4);
    }
  };
  if (!pack(density)) {
    // The largest density that packs, by bisection (each try only packs rectangles), to name it.
    double lo = 0, hi = density;
    for (int i = 0; i < 40 && lo * 1.0001 < hi; ++i) {
      const double mid = i == 0 ? density * 1e-3 : 0.5 * (lo + hi);
      (pack(mid) ? lo : hi) = mid;
    }
    const std::string need = "texels_per_unit: at " + format_number(density) + " texels per unit the lightmap charts (" +
                             std::to_string(charts.size()) + ") do not fit a " + std::to_string(o.max_size) + " x " +
                             std::to_string(o.max_size) + " atlas (max_size)";
    const double fits = std::floor(lo * 1000) / 1000;
    return Status{ErrorCode::out_of_memory, "texels_per_unit",
                  fits > 0 ? need + "; " + format_number(fits) + " texels per unit would fit"
                           : need + " at any density: too many charts for the atlas"};
  }

  // Vertices split per chart, in triangle order; a corner's uv is its projection, moved so that
  // the chart's lower-left corner is the centre of its first texel.
  std::unordered_map<std::uint64_t, std::uint32_t> new_vertex;
  out.triangles.resize(tri_count);
  for (std::size_t t = 0; t < tri_count; ++t) {
    const std::uint32_t id = out.chart_of_triangle[t];
    const ChartBuild& c = charts[id];
    const auto& rect = out.charts[id];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[t][static_cast<std::size_t>(k)];
      const auto [it, added] = new_vertex.try_emplace((std::uint64_t{id} << 32) | v, static_cast<std::uint32_t>(out.uvs.size()));
      if (added) {
        V2 texel(rect.x0 + 0.5, rect.y0 + 0.5);
        if (!c.degenerate) {
          const V3 p = mesh.positions[v].cast<double>();
          texel += (V2(p.dot(c.t), p.dot(c.b)) - c.lo) * density;
        }
        out.uvs.emplace_back(static_cast<float>(texel.x() / out.width), static_cast<float>(texel.y() / out.height));
        out.source_vertex.push_back(v);
      }
      out.triangles[t][static_cast<std::size_t>(k)] = it->second;
    }
  }
  return out;
}

}  // namespace

Mesh world_space_mesh(const Mesh& mesh, const Mat4& model_f) {
  Mesh world;
  const Eigen::Matrix4d model = model_f.cast<double>();
  const Eigen::Matrix3d normal_matrix = model.topLeftCorner<3, 3>().inverse().transpose();
  world.triangles = mesh.triangles;
  world.positions.resize(mesh.positions.size());
  world.normals.resize(mesh.normals.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    world.positions[v] = (model * mesh.positions[v].cast<double>().homogeneous()).head<3>().cast<float>();
  }
  for (std::size_t v = 0; v < mesh.normals.size(); ++v) {
    const V3 n = normal_matrix * mesh.normals[v].cast<double>();
    world.normals[v] = (n.norm() > 0 && n.allFinite() ? V3(n.normalized()) : V3::Zero()).cast<float>();
  }
  return world;
}

Result<Mesh> with_lightmap_uvs(const Mesh& mesh, const LightmapUnwrap& u) {
  if (u.triangles.size() != mesh.triangles.size() || u.uvs.size() != u.source_vertex.size()) {
    return Status{ErrorCode::invalid_argument, "unwrap",
                  "unwrap: made for a mesh of " + std::to_string(u.triangles.size()) + " triangles, this one has " +
                      std::to_string(mesh.triangles.size())};
  }
  for (const std::uint32_t v : u.source_vertex) {
    if (v >= mesh.positions.size()) {
      return Status{ErrorCode::invalid_argument, "unwrap", "unwrap: a source vertex is out of range for this mesh"};
    }
  }
  try {
    Mesh out;
    auto copy = [&](const auto& from, auto& to) {
      if (from.size() != mesh.positions.size()) return;  // absent (or invalid: validate_mesh reports it)
      to.resize(u.source_vertex.size());
      for (std::size_t i = 0; i < u.source_vertex.size(); ++i) to[i] = from[u.source_vertex[i]];
    };
    copy(mesh.positions, out.positions);
    copy(mesh.normals, out.normals);
    copy(mesh.uvs, out.uvs);
    copy(mesh.colors, out.colors);
    copy(mesh.tangents, out.tangents);
    out.triangles = u.triangles;
    out.groups = mesh.groups;
    out.lightmap_uvs = u.uvs;
    return out;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "mesh", "mesh: out of memory while splitting it for its lightmap"};
  }
}

Result<LightmapUnwrap> lightmap_from_mesh_uvs(const Mesh& mesh, double texels_per_unit, int max_size) {
  LightmapUvOptions checked;
  checked.texels_per_unit = texels_per_unit, checked.max_size = max_size;
  FACET_TRY(check_options(checked));
  FACET_TRY(validate_mesh(mesh));
  if (mesh.lightmap_uvs.empty()) return Status{ErrorCode::invalid_argument, "lightmap_uvs", "lightmap_uvs: the mesh has none"};
  for (std::size_t v = 0; v < mesh.lightmap_uvs.size(); ++v) {
    const Vec2& uv = mesh.lightmap_uvs[v];
    if (!(uv.x() >= 0.0f && uv.x() <= 1.0f && uv.y() >= 0.0f && uv.y() <= 1.0f)) {
      return Status{ErrorCode::invalid_argument, "lightmap_uvs",
                    "lightmap_uvs: vertex " + std::to_string(v) + " lies outside [0, 1] (" + format_number(uv.x()) + ", " +
                        format_number(uv.y()) + "): a lightmap's coordinates must lie in its atlas"};
    }
  }
  double uv_area = 0, world_area = 0;
  for (const auto& t : mesh.triangles) {
    const Vec2 &a = mesh.lightmap_uvs[t[0]], &b = mesh.lightmap_uvs[t[1]], &c = mesh.lightmap_uvs[t[2]];
    uv_area += 0.5 * std::abs(double(b.x() - a.x()) * double(c.y() - a.y()) - double(b.y() - a.y()) * double(c.x() - a.x()));
    const V3 p0 = mesh.positions[t[0]].cast<double>(), p1 = mesh.positions[t[1]].cast<double>(), p2 = mesh.positions[t[2]].cast<double>();
    const double w = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    if (std::isfinite(w)) world_area += w;
  }
  const double side = uv_area > 0 ? std::ceil(texels_per_unit * std::sqrt(world_area / uv_area)) : 1.0;
  if (!(side <= double(max_size))) {
    return Status{ErrorCode::out_of_memory, "texels_per_unit",
                  "texels_per_unit: at " + format_number(texels_per_unit) + " texels per unit the mesh's lightmap coordinates need a " +
                      format_number(side) + " texel atlas, more than " + std::to_string(max_size) + " (max_size); " +
                      format_number(texels_per_unit * double(max_size) / side) + " texels per unit would fit"};
  }
  try {
    LightmapUnwrap u;
    u.width = u.height = std::max(1, static_cast<int>(side));
    u.source_vertex.resize(mesh.positions.size());
    for (std::size_t v = 0; v < u.source_vertex.size(); ++v) u.source_vertex[v] = static_cast<std::uint32_t>(v);
    u.triangles = mesh.triangles;
    u.uvs = mesh.lightmap_uvs;
    u.chart_of_triangle.assign(mesh.triangles.size(), 0);
    u.charts.push_back({0, 0, u.width, u.height});
    return u;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "mesh", "mesh: out of memory for its lightmap coordinates"};
  }
}

Result<LightmapUnwrap> unwrap_lightmap(const Mesh& mesh, const LightmapUvOptions& options) {
  FACET_TRY(check_options(options));
  FACET_TRY(validate_mesh(mesh));
  try {
    return unwrap(mesh, options);
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "mesh", "mesh: out of memory while cutting lightmap charts for " +
                                                        std::to_string(mesh.triangles.size()) + " triangles"};
  }
}

}  // namespace facet
