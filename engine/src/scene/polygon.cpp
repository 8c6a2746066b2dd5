#include "scene/polygon.hpp"

#include <cmath>

namespace facet {

namespace {

// Twice the signed area of (a, b, c) in the plane: > 0 counter-clockwise.
double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// p inside or on the counter-clockwise triangle (a, b, c).
bool inside(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

void fan(std::uint32_t n, std::vector<std::array<std::uint32_t, 3>>& out) {
  for (std::uint32_t k = 1; k + 1 < n; ++k) out.push_back({0, k, k + 1});
}

}  // namespace

void triangulate_polygon(std::span<const Eigen::Vector3d> corners, std::vector<std::array<std::uint32_t, 3>>& out) {
  const auto n = static_cast<std::uint32_t>(corners.size());
  if (n < 3) return;
  if (n == 3) return fan(n, out);
  // Newell's normal: the polygon's plane, and its winding as seen from the normal's side.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::uint32_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = corners[i];
    const Eigen::Vector3d& b = corners[(i + 1) % n];
    normal += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                              (a.x() - b.x()) * (a.y() + b.y()));
  }
  if (!(normal.norm() > 0.0) || !normal.allFinite()) return fan(n, out);
  // Project onto the plane, seen from the normal's side: the polygon is counter-clockwise there.
  Eigen::Index axis = 0;
  normal.cwiseAbs().maxCoeff(&axis);
  const int u = static_cast<int>((axis + 1) % 3), v = static_cast<int>((axis + 2) % 3);
  const double flip = normal[axis] > 0.0 ? 1.0 : -1.0;
  std::vector<Eigen::Vector2d> p(n);
  for (std::uint32_t i = 0; i < n; ++i) p[i] = Eigen::Vector2d(corners[i][u], flip * corners[i][v]);
  bool convex = true;
  for (std::uint32_t i = 0; i < n && convex; ++i) convex = cross2(p[i], p[(i + 1) % n], p[(i + 2) % n]) >= 0.0;
  if (convex) return fan(n, out);
  std::vector<std::uint32_t> ring(n);
  for (std::uint32_t i = 0; i < n; ++i) ring[i] = i;
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    bool clipped = false;
    for (std::size_t k = 0; k < m && !clipped; ++k) {
      const std::uint32_t a = ring[(k + m - 1) % m], b = ring[k], c = ring[(k + 1) % m];
      if (!(cross2(p[a], p[b], p[c]) > 0.0)) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        const std::uint32_t q = ring[j];
        if (q == a || q == b || q == c) continue;
        // Only a corner that is not on the ear's outline can block it (a repeated position can).
        if (p[q] == p[a] || p[q] == p[b] || p[q] == p[c]) continue;
        empty = !inside(p[q], p[a], p[b], p[c]);
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) {  // self-intersecting: finish as a fan of what is left
      for (std::size_t k = 1; k + 1 < ring.size(); ++k) out.push_back({ring[0], ring[k], ring[k + 1]});
      return;
    }
  }
  out.push_back({ring[0], ring[1], ring[2]});
}

}  // namespace facet
