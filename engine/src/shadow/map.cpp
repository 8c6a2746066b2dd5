#include "shadow/map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "common/look_at.hpp"

namespace facet::shadow {

// Cones wider than this (half-angle, degrees) get a cube: a single perspective face would spend
// most of its texels far off the axis.
constexpr double kWidestSpotFace = 75.0;

namespace {

constexpr double kPi = 3.14159265358979323846;
// The near plane stays at least this fraction of the far plane (window depth keeps its precision).
constexpr double kNearFraction = 1e-3;


Eigen::Vector3d up_for(const Eigen::Vector3d& forward) { return light_up(forward); }

// GL's glFrustum for a square field of view; GL's glOrtho.
Eigen::Matrix4d perspective(double tan_half, double n, double f) {
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = p(1, 1) = 1.0 / tan_half;
  p(2, 2) = -(f + n) / (f - n);
  p(2, 3) = -2.0 * f * n / (f - n);
  p(3, 2) = -1.0;
  return p;
}
Eigen::Matrix4d orthographic(double l, double r, double b, double t, double n, double f) {
  Eigen::Matrix4d p = Eigen::Matrix4d::Identity();
  p(0, 0) = 2.0 / (r - l), p(0, 3) = -(r + l) / (r - l);
  p(1, 1) = 2.0 / (t - b), p(1, 3) = -(t + b) / (t - b);
  p(2, 2) = -2.0 / (f - n), p(2, 3) = -(f + n) / (f - n);
  return p;
}

// The eight corners of box i, through `m`.
template <class F>
void for_corners(const CasterBounds& c, std::size_t i, const Eigen::Matrix4d& m, const F& f) {
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d p((k & 1) ? c.hi[i].x() : c.lo[i].x(), (k & 2) ? c.hi[i].y() : c.lo[i].y(),
                            (k & 4) ? c.hi[i].z() : c.lo[i].z());
    f((m * p.homogeneous()).head<3>().eval());
  }
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

std::size_t ShadowMap::bytes(const Light& light) {
  const auto r = static_cast<std::size_t>(std::clamp(light.shadow.resolution, 16, 16384));
  return static_cast<std::size_t>(shadow_map_faces(light)) * r * r * sizeof(float);
}

DepthView ShadowMap::depth_view(int f) {
  const std::size_t texels = static_cast<std::size_t>(resolution_) * static_cast<std::size_t>(resolution_);
  return {depth_.data() + static_cast<std::size_t>(f) * texels, resolution_, resolution_,
          static_cast<std::size_t>(resolution_) * sizeof(float), false};
}

void ShadowMap::plan(const Light& light, const CasterBounds& casters, const Eigen::Matrix4d& camera_view,
                     const Eigen::Matrix4d& camera_projection) {
  faces_ = 0;
  resolution_ = light.shadow.resolution;
  const int taps = shadow_filter_width(light.shadow.filter);
  const Eigen::Matrix4d eye_to_world = camera_view.inverse();
  double texel = 0.0, tan_half = 1.0;
  int kind = MapLookup::orthographic;
  if (casters.empty()) return;
  // Margin of the perspective faces: the filter's reach plus a texel, on each side.
  const double margin = std::floor(0.5 * taps) + 2.0;
  const double widen = resolution_ / (resolution_ - 2.0 * margin);
  const Eigen::Vector3d position = light.position.cast<double>();
  const double cone = light.spot_shape == SpotShape::smooth_cone ? light.spot_outer_deg : light.spot_cutoff_deg;

  if (light.type == LightType::directional) {
    kind = MapLookup::orthographic;
    const Eigen::Vector3d forward = light.direction.cast<double>().normalized();
    const Eigen::Matrix4d view = look_along(Eigen::Vector3d::Zero(), forward, up_for(forward));
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i < casters.lo.size(); ++i) {
      for_corners(casters, i, view, [&](const Eigen::Vector3d& q) { box.extend(q); });
    }
    // The camera frustum's footprint across the light (its corners in light space): a caster
    // outside it cannot shade a visible point, whose shadow ray runs along the light.
    const Eigen::Matrix4d clip_to_light = view * (camera_projection * camera_view).inverse();
    // An infinite projection's far corners lie at infinity (w = 0): no footprint then.
    Eigen::AlignedBox2d footprint;
    bool bounded = true;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector4d c((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0, 1.0);
      const Eigen::Vector4d q = clip_to_light * c;
      bounded = bounded && std::abs(q.w()) > 1e-12 * q.head<3>().norm();
      if (q.w() != 0.0) footprint.extend(Eigen::Vector2d(q.x() / q.w(), q.y() / q.w()));
    }
    if (!bounded) footprint.setEmpty();
    Eigen::Vector2d lo = box.min().head<2>(), hi = box.max().head<2>();
    if (!footprint.isEmpty() && footprint.min().allFinite() && footprint.max().allFinite()) {
      lo = lo.cwiseMax(footprint.min());
      hi = hi.cwiseMin(footprint.max());
    }
    // A little room around the casters, so that none lies on the map's border.
    const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    const double depth = box.max().z() - box.min().z();
    if (!finite_positive(extent) || !std::isfinite(depth) || depth < 0.0) return;  // nothing, or a point
    const double pad = extent * margin / resolution_;
    lo.array() -= pad, hi.array() += pad;
    const double z_pad = 1e-3 * std::max(depth, extent);
    Face& f = face_[0];
    f.view = view;
    f.projection = orthographic(lo.x(), hi.x(), lo.y(), hi.y(), -box.max().z() - z_pad, -box.min().z() + z_pad);
    texel = std::max(hi.x() - lo.x(), hi.y() - lo.y()) / resolution_;
    faces_ = 1;
  } else if (shadow_map_faces(light) == 1) {  // a spot light
    kind = MapLookup::perspective;
    const Eigen::Vector3d forward = light.direction.cast<double>().normalized();
    const Eigen::Matrix4d view = look_along(position, forward, up_for(forward));
    double near = std::numeric_limits<double>::infinity(), far = 0.0;
    for (std::size_t i = 0; i < casters.lo.size(); ++i) {
      for_corners(casters, i, view, [&](const Eigen::Vector3d& q) {
        near = std::min(near, -q.z());
        far = std::max(far, -q.z());
      });
    }
    if (!finite_positive(far)) return;  // every caster behind the light
    far *= 1.0 + 1e-3;
    near = std::max(near * (1.0 - 1e-3), far * kNearFraction);
    tan_half = std::tan(cone * kPi / 180.0) * widen;
    Face& f = face_[0];
    f.view = view;
    f.projection = perspective(tan_half, near, far);
    faces_ = 1;
  } else {  // a point light, or a wide spot light: six faces along the world axes
    kind = MapLookup::cube;
    double near = std::numeric_limits<double>::infinity(), far = 0.0;
    for (std::size_t i = 0; i < casters.lo.size(); ++i) {
      const Eigen::Vector3d nearest = position.cwiseMax(casters.lo[i]).cwiseMin(casters.hi[i]);
      near = std::min(near, (nearest - position).norm());
      for_corners(casters, i, Eigen::Matrix4d::Identity(),
                  [&](const Eigen::Vector3d& q) { far = std::max(far, (q - position).norm()); });
    }
    if (!finite_positive(far)) return;
    far *= 1.0 + 1e-3;
    near = std::max(near * (1.0 - 1e-3), far * kNearFraction);
    tan_half = widen;  // 45 degrees, widened
    // +x, -x, +y, -y, +z, -z (GL's order), each with an up vector off its axis.
    static const double kAxes[6][6] = {{1, 0, 0, 0, -1, 0},  {-1, 0, 0, 0, -1, 0}, {0, 1, 0, 0, 0, 1},
                                       {0, -1, 0, 0, 0, -1}, {0, 0, 1, 0, -1, 0},  {0, 0, -1, 0, -1, 0}};
    for (int k = 0; k < 6; ++k) {
      Face& f = face_[k];
      f.view = look_along(position, Eigen::Vector3d(kAxes[k][0], kAxes[k][1], kAxes[k][2]),
                          Eigen::Vector3d(kAxes[k][3], kAxes[k][4], kAxes[k][5]));
      f.projection = perspective(tan_half, near, far);
    }
    faces_ = 6;
  }
  const std::size_t texels =
      static_cast<std::size_t>(faces_) * static_cast<std::size_t>(resolution_) * static_cast<std::size_t>(resolution_);
  if (depth_.size() != texels) {  // new images hold zeros, not far depth: every tile must be written
    depth_.resize(texels);
    dirty_tile_size_ = 0;
  }
  // What the lookup kernels read, in float.
  MapLookup& m = lookup_;
  m = MapLookup{};
  m.kind = kind;
  m.resolution = resolution_;
  m.taps = taps;
  m.depth = depth_.data();
  for (int k = 0; k < faces_; ++k) {
    const Eigen::Matrix4d to_clip = face_[k].projection * face_[k].view * eye_to_world;
    for (int i = 0; i < 16; ++i) m.to_clip[k][i] = static_cast<float>(to_clip(i / 4, i % 4));
  }
  m.texel = static_cast<float>(texel);
  m.texel_per_w = static_cast<float>(2.0 * tan_half / resolution_);
  m.reach = static_cast<float>(0.5 * taps + 0.5);
  m.bias_normal = light.shadow.bias.normal;
  m.bias_constant = light.shadow.bias.constant;
  m.bias_slope = light.shadow.bias.slope;
  m.directional = light.type == LightType::directional ? 1 : 0;
  const Eigen::Vector3d at = light.type == LightType::directional
                                 ? Eigen::Vector3d(-(camera_view.topLeftCorner<3, 3>() * light.direction.cast<double>()).normalized())
                                 : Eigen::Vector3d((camera_view * position.homogeneous()).head<3>());
  for (int c = 0; c < 3; ++c) m.light[c] = static_cast<float>(at[c]);
  for (int i = 0; i < 9; ++i) m.eye_to_world[i] = static_cast<float>(eye_to_world(i / 3, i % 3));
}

std::uint8_t* ShadowMap::dirty_tiles(int f, int tile_size) {
  const std::size_t per_face = static_cast<std::size_t>((resolution_ + tile_size - 1) / tile_size) *
                               static_cast<std::size_t>((resolution_ + tile_size - 1) / tile_size);
  if (dirty_tile_size_ != tile_size || dirty_.size() != 6 * per_face) {
    dirty_.assign(6 * per_face, 1);
    dirty_tile_size_ = tile_size;
  }
  return dirty_.data() + static_cast<std::size_t>(f) * per_face;
}

void ShadowMap::visibility(std::size_t count, const float* px, const float* py, const float* pz, const float* nx,
                           const float* ny, const float* nz, std::size_t stride, float* visible) const {
  if (faces_ == 0) {
    for (std::size_t i = 0; i < count; ++i) visible[i] = 1.0f;
    return;
  }
  (kernel_ ? kernel_ : map_visibility_scalar)(lookup_, count, px, py, pz, nx, ny, nz, stride, visible);
}

// The scalar twin of the SIMD lookup (map_simd.hpp): the same float operations in the same
// order. Moved d along its normal, a plane at angle t to the light clears its own depth by
// d / cos t along the ray, where the filter's taps within r of the point see it at most r tan t
// nearer: d = r sin t suffices, so a normal bias of one filter radius clears any angle.
void map_visibility_scalar(const MapLookup& m, std::size_t count, const float* px, const float* py, const float* pz,
                           const float* nx, const float* ny, const float* nz, std::size_t stride, float* visible) {
  const int n = m.resolution;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t at = i * stride;
    const float x = px[at], y = py[at], z = pz[at], a = nx[at], b = ny[at], c = nz[at];
    const float lx = m.directional ? m.light[0] : m.light[0] - x;
    const float ly = m.directional ? m.light[1] : m.light[1] - y;
    const float lz = m.directional ? m.light[2] : m.light[2] - z;
    const float n2 = (a * a + b * b) + c * c, l2 = (lx * lx + ly * ly) + lz * lz;
    bool valid = n2 > 0.0f && l2 > 0.0f && n2 < 1e30f && l2 < 1e30f && (x - x) == 0.0f && (y - y) == 0.0f &&
                 (z - z) == 0.0f;
    const float inv_n = 1.0f / std::sqrt(n2), inv_l = 1.0f / std::sqrt(l2);
    float cos_nl = (((a * lx + b * ly) + c * lz) * inv_n) * inv_l;
    cos_nl = std::min(std::max(cos_nl, 0.0f), 1.0f);
    const float sin_nl = std::sqrt(std::max(1.0f - cos_nl * cos_nl, 0.0f));
    const float tan_nl = std::min(sin_nl / cos_nl, kMaxSlopeTangent);
    int face = 0;
    if (m.kind == MapLookup::cube) {
      const float dx = x - m.light[0], dy = y - m.light[1], dz = z - m.light[2];
      const float* r = m.eye_to_world;
      const float w[3] = {(r[0] * dx + r[1] * dy) + r[2] * dz, (r[3] * dx + r[4] * dy) + r[5] * dz,
                          (r[6] * dx + r[7] * dy) + r[8] * dz};
      const float ax = std::abs(w[0]), ay = std::abs(w[1]), az = std::abs(w[2]);
      const int axis = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
      face = 2 * axis + (w[axis] < 0.0f ? 1 : 0);
    }
    const float* row = m.to_clip[face];
    float cc[4];
    for (int r = 0; r < 4; ++r) cc[r] = ((row[4 * r] * x + row[4 * r + 1] * y) + row[4 * r + 2] * z) + row[4 * r + 3];
    const float texel = m.kind == MapLookup::orthographic ? m.reach * m.texel : m.reach * (m.texel_per_w * std::max(cc[3], 0.0f));
    const float along_n = (texel * m.bias_normal) * inv_n;
    const float along_l = (texel * (m.bias_constant + m.bias_slope * tan_nl)) * inv_l;
    const float o0 = along_n * a + along_l * lx, o1 = along_n * b + along_l * ly, o2 = along_n * c + along_l * lz;
    for (int r = 0; r < 4; ++r) cc[r] = cc[r] + ((row[4 * r] * o0 + row[4 * r + 1] * o1) + row[4 * r + 2] * o2);
    valid = valid && cc[3] > 0.0f;
    const float inv_w = 1.0f / cc[3];
    const float half = 0.5f * static_cast<float>(n);
    const float u = (cc[0] * inv_w + 1.0f) * half, v = (1.0f - cc[1] * inv_w) * half;
    const float depth = std::min(std::max(0.5f * (cc[2] * inv_w) + 0.5f, 0.0f), 1.0f);
    const float shift = m.taps == 1 ? 0.0f : 0.5f * static_cast<float>(m.taps) - 0.5f;
    const float su = u - shift, sv = v - shift;
    const float fu = std::floor(su), fv = std::floor(sv);
    valid = valid && fu > -1e9f && fu < 1e9f && fv > -1e9f && fv < 1e9f;
    if (!valid) {
      visible[i] = 1.0f;
      continue;
    }
    const int x0 = static_cast<int>(fu), y0 = static_cast<int>(fv);
    const float fx = su - fu, fy = sv - fv;
    const float* texels = m.depth + static_cast<std::size_t>(face) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    // Lit where the texel is outside the map (nothing casts there) or not nearer than the point.
    auto lit = [&](int tx, int ty) {
      if (tx < 0 || tx >= n || ty < 0 || ty >= n) return true;
      return depth <= texels[static_cast<std::size_t>(ty) * static_cast<std::size_t>(n) + static_cast<std::size_t>(tx)];
    };
    if (m.taps == 1) {
      visible[i] = lit(x0, y0) ? 1.0f : 0.0f;
      continue;
    }
    const int last = m.taps - 1;
    float sum = 0.0f;
    for (int j = 0; j <= last; ++j) {
      float r = 0.0f;
      for (int k = 0; k <= last; ++k) {
        const float w = k == 0 ? 1.0f - fx : k == last ? fx : 1.0f;
        r = r + (lit(x0 + k, y0 + j) ? w : 0.0f);
      }
      const float wy = j == 0 ? 1.0f - fy : j == last ? fy : 1.0f;
      sum = sum + wy * r;
    }
    visible[i] = sum / static_cast<float>(last * last);
  }
}

}  // namespace facet::shadow

namespace facet {

int shadow_filter_width(ShadowFilter filter) noexcept {
  switch (filter) {
    case ShadowFilter::none: return 1;
    case ShadowFilter::pcf2x2: return 2;
    case ShadowFilter::pcf3x3: return 3;
    case ShadowFilter::pcf5x5: return 5;
  }
  return 1;
}

int shadow_map_faces(const Light& light) noexcept {
  if (light.type == LightType::directional) return 1;
  if (light.type == LightType::point) return 6;
  const double cone = light.spot_shape == SpotShape::smooth_cone ? light.spot_outer_deg : light.spot_cutoff_deg;
  return cone > shadow::kWidestSpotFace ? 6 : 1;
}

}  // namespace facet
