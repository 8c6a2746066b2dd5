// Internal: triangulating a polygon (an OBJ face of more than three corners) as Blender and assimp
// do: ear clipping in the polygon's plane. Holes are not supported (OBJ faces have none).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace facet {

// The triangles of the polygon whose corners, in order, are `corners` (any winding), as triples of
// indices into `corners`, appended to `out` (n - 2 of them for n >= 3 corners). Each triangle
// keeps the polygon's winding. A convex polygon gets the fan from corner 0 (exactly what a fan
// triangulation gives); a concave one is ear-clipped in the plane of its Newell normal, taking at
// each step the first ear in corner order, so the result depends on the corners alone. A polygon
// that is degenerate (no area) or self-intersecting (no ear left) is finished as a fan.
void triangulate_polygon(std::span<const Eigen::Vector3d> corners, std::vector<std::array<std::uint32_t, 3>>& out);

}  // namespace facet
