// Internal: a shadowed light as every shadow method's visibility query sees it, in the camera's
// eye space, and the test shared by all methods for points the light surely cannot light.
#pragma once

#include <cmath>

namespace facet::shadow {

struct LightTarget {
  // A position (point, spot) or the unit direction towards a directional light.
  bool directional = false;
  float x = 0, y = 0, z = 0;
  // Where the light cannot reach (its visibility does not matter there, so no query is made): a
  // spot light's cone (unit axis, the way the light travels; outside when the cosine to the axis
  // is below cos_outer) and a range (0 = none).
  bool spot = false;
  float axis_x = 0, axis_y = 0, axis_z = 0, cos_outer = -1;
  float range = 0;
};

// False only where the light surely gives nothing: the point faces away from it (n . l below
// -1e-4 |n| |l|, far beyond the lighting kernels' rounding, which decides n . l > 0 on normalised
// vectors), lies outside a spot light's cone (cosine below cos_outer - 1e-4) or beyond its range
// (by 0.01 %). Elsewhere the method is asked, so the points skipped cannot change a pixel.
inline bool may_be_lit(const LightTarget& t, float px, float py, float pz, float nx, float ny, float nz) {
  double lx, ly, lz;
  if (t.directional) {
    lx = t.x, ly = t.y, lz = t.z;
  } else {
    lx = double(t.x) - px, ly = double(t.y) - py, lz = double(t.z) - pz;
  }
  const double l2 = lx * lx + ly * ly + lz * lz, n2 = double(nx) * nx + double(ny) * ny + double(nz) * nz;
  if (!(l2 > 0.0 && n2 > 0.0 && l2 < 1e300 && n2 < 1e300)) return true;  // no direction (or not finite): ask
  const double length = std::sqrt(l2);
  if (nx * lx + ny * ly + nz * lz < -1e-4 * std::sqrt(n2) * length) return false;
  if (t.directional) return true;
  if (t.range > 0.0f && length > 1.0001 * t.range) return false;
  if (t.spot) {
    const double cos_angle = -(lx * t.axis_x + ly * t.axis_y + lz * t.axis_z) / length;
    if (cos_angle < double(t.cos_outer) - 1e-4) return false;
  }
  return true;
}

}  // namespace facet::shadow
