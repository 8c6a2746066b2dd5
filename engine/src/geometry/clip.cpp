#include "geometry/clip.hpp"

namespace facet::geometry {
namespace {

float plane_distance(const ClipVertex& v, int plane, const ClipPlanes& p) noexcept {
  switch (plane) {
    case 0: return v.w + v.z;
    case 1: return v.w - v.z;
    case 2: return p.guard_x * v.w + v.x;
    case 3: return p.guard_x * v.w - v.x;
    case 4: return p.guard_y * v.w + v.y;
    default: return p.guard_y * v.w - v.y;
  }
}

ClipVertex intersect(const ClipVertex& inside, const ClipVertex& outside, float d_in, float d_out,
                     int attribute_count) noexcept {
  const float t = d_in / (d_in - d_out);
  ClipVertex v;
  v.x = inside.x + t * (outside.x - inside.x);
  v.y = inside.y + t * (outside.y - inside.y);
  v.z = inside.z + t * (outside.z - inside.z);
  v.w = inside.w + t * (outside.w - inside.w);
  for (int k = 0; k < attribute_count; ++k) v.attr[k] = inside.attr[k] + t * (outside.attr[k] - inside.attr[k]);
  for (int k = attribute_count; k < kMaxAttributes; ++k) v.attr[k] = 0.0f;
  return v;
}

}  // namespace

int clip_triangle(const ClipVertex& a, const ClipVertex& b, const ClipVertex& c, std::uint32_t outcode_union,
                  const ClipPlanes& planes, int attribute_count, ClipVertex* out) noexcept {
  ClipVertex buffer[2][kMaxClippedVertices];
  ClipVertex* src = buffer[0];
  ClipVertex* dst = buffer[1];
  src[0] = a;
  src[1] = b;
  src[2] = c;
  int count = 3;
  for (int plane = 0; plane < 6 && count > 0; ++plane) {
    if (!(outcode_union & (1u << plane))) continue;
    int n = 0;
    for (int i = 0; i < count; ++i) {
      if (n + 2 > kMaxClippedVertices) return 0;
      const ClipVertex& cur = src[i];
      const ClipVertex& prev = src[(i + count - 1) % count];
      const float d_cur = plane_distance(cur, plane, planes);
      const float d_prev = plane_distance(prev, plane, planes);
      const bool cur_in = d_cur >= 0.0f, prev_in = d_prev >= 0.0f;
      if (cur_in != prev_in) {
        dst[n++] = prev_in ? intersect(prev, cur, d_prev, d_cur, attribute_count)
                           : intersect(cur, prev, d_cur, d_prev, attribute_count);
      }
      if (cur_in) dst[n++] = cur;
    }
    count = n;
    ClipVertex* t = src;
    src = dst;
    dst = t;
  }
  for (int i = 0; i < count; ++i) out[i] = src[i];
  return count;
}

}  // namespace facet::geometry
