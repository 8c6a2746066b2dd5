#include "shadow/map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace facet::shadow {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Cones wider than this (half-angle, degrees) get a cube: a single perspective face would spend
// most of its texels far off the axis.
constexpr double kWidestSpotFace = 75.0;
// The near plane stays at least this fraction of the far plane (window depth keeps its precision).
constexpr double kNearFraction = 1e-3;
// The slope bias's tangent is capped (grazing light would push points through thin casters).
constexpr double kMaxSlope = 10.0;

// Texels a filter reaches beyond the point's texel, and the filter's width in texels.
int taps_of(ShadowFilter f) {
  switch (f) {
    case ShadowFilter::none: return 1;
    case ShadowFilter::pcf2x2: return 2;
    case ShadowFilter::pcf3x3: return 3;
    case ShadowFilter::pcf5x5: return 5;
  }
  return 1;
}

// A right-handed view looking from `eye` along unit `forward`, with `up` not parallel to it.
Eigen::Matrix4d look_along(const Eigen::Vector3d& eye, const Eigen::Vector3d& forward, const Eigen::Vector3d& up) {
  const Eigen::Vector3d s = forward.cross(up).normalized();
  const Eigen::Vector3d u = s.cross(forward);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = forward.dot(eye);
  return m;
}

// An up vector for a view along `forward`: world +y unless the light is within ~8 degrees of it,
// then +x. Fixed by the light alone, so the map does not turn with the camera.
Eigen::Vector3d up_for(const Eigen::Vector3d& forward) {
  return std::abs(forward.y()) < 0.99 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
}

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
  const bool cube = light.type == LightType::point ||
                    (light.type == LightType::spot &&
                     (light.spot_shape == SpotShape::smooth_cone ? light.spot_outer_deg : light.spot_cutoff_deg) >
                         kWidestSpotFace);
  return (cube ? 6 : 1) * r * r * sizeof(float);
}

DepthView ShadowMap::depth_view(int f) {
  Face& face = face_[f];
  return {face.depth.data(), resolution_, resolution_, static_cast<std::size_t>(resolution_) * sizeof(float), false};
}

void ShadowMap::plan(const Light& light, const CasterBounds& casters, const Eigen::Matrix4d& camera_view,
                     const Eigen::Matrix4d& camera_projection) {
  faces_ = 0;
  resolution_ = light.shadow.resolution;
  taps_ = taps_of(light.shadow.filter);
  reach_ = 0.5 * taps_ + 0.5;
  bias_ = light.shadow.bias;
  eye_to_world_ = camera_view.inverse();
  if (casters.empty()) return;
  // Margin of the perspective faces: the filter's reach plus a texel, on each side.
  const double margin = std::floor(0.5 * taps_) + 2.0;
  const double widen = resolution_ / (resolution_ - 2.0 * margin);
  const Eigen::Vector3d position = light.position.cast<double>();
  const double cone = light.spot_shape == SpotShape::smooth_cone ? light.spot_outer_deg : light.spot_cutoff_deg;

  if (light.type == LightType::directional) {
    kind_ = Kind::orthographic;
    const Eigen::Vector3d forward = light.direction.cast<double>().normalized();
    const Eigen::Matrix4d view = look_along(Eigen::Vector3d::Zero(), forward, up_for(forward));
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i < casters.lo.size(); ++i) {
      for_corners(casters, i, view, [&](const Eigen::Vector3d& q) { box.extend(q); });
    }
    // The camera frustum's footprint across the light (its corners in light space): a caster
    // outside it cannot shade a visible point, whose shadow ray runs along the light.
    const Eigen::Matrix4d clip_to_light = view * (camera_projection * camera_view).inverse();
    Eigen::AlignedBox2d footprint;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector4d c((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0, 1.0);
      const Eigen::Vector4d q = clip_to_light * c;
      if (q.w() != 0.0) footprint.extend(Eigen::Vector2d(q.x() / q.w(), q.y() / q.w()));
    }
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
    texel_ = std::max(hi.x() - lo.x(), hi.y() - lo.y()) / resolution_;
    faces_ = 1;
  } else if (light.type == LightType::spot && cone <= kWidestSpotFace) {
    kind_ = Kind::perspective;
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
    tan_half_ = std::tan(cone * kPi / 180.0) * widen;
    Face& f = face_[0];
    f.view = view;
    f.projection = perspective(tan_half_, near, far);
    faces_ = 1;
  } else {  // a point light, or a wide spot light: six faces along the world axes
    kind_ = Kind::cube;
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
    tan_half_ = widen;  // 45 degrees, widened
    // +x, -x, +y, -y, +z, -z (GL's order), each with an up vector off its axis.
    static const double kAxes[6][6] = {{1, 0, 0, 0, -1, 0},  {-1, 0, 0, 0, -1, 0}, {0, 1, 0, 0, 0, 1},
                                       {0, -1, 0, 0, 0, -1}, {0, 0, 1, 0, -1, 0},  {0, 0, -1, 0, -1, 0}};
    for (int k = 0; k < 6; ++k) {
      Face& f = face_[k];
      f.view = look_along(position, Eigen::Vector3d(kAxes[k][0], kAxes[k][1], kAxes[k][2]),
                          Eigen::Vector3d(kAxes[k][3], kAxes[k][4], kAxes[k][5]));
      f.projection = perspective(tan_half_, near, far);
    }
    light_eye_ = (camera_view * position.homogeneous()).head<3>();
    faces_ = 6;
  }
  const auto texels = static_cast<std::size_t>(resolution_) * static_cast<std::size_t>(resolution_);
  for (int k = 0; k < faces_; ++k) {
    Face& f = face_[k];
    f.from_eye = f.view * eye_to_world_;
    f.depth.resize(texels);
  }
}

double ShadowMap::lookup(const Face& f, const Eigen::Vector3d& q) const {
  const Eigen::Vector4d c = f.projection * q.homogeneous();
  if (!(c.w() > 0.0)) return 1.0;  // behind a perspective face's light: no caster there
  const double inv_w = 1.0 / c.w();
  const double n = resolution_;
  const double u = (c.x() * inv_w + 1.0) * 0.5 * n, v = (1.0 - c.y() * inv_w) * 0.5 * n;
  const double z = std::clamp(0.5 * c.z() * inv_w + 0.5, 0.0, 1.0);
  if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(z)) return 1.0;
  auto lit = [&](double x, double y) -> double {  // texel (x, y): outside the map, nothing casts
    if (x < 0.0 || y < 0.0 || x >= n || y >= n) return 1.0;
    const std::size_t at = static_cast<std::size_t>(y) * static_cast<std::size_t>(resolution_) + static_cast<std::size_t>(x);
    return z <= double(f.depth[at]) ? 1.0 : 0.0;
  };
  if (taps_ == 1) return lit(std::floor(u), std::floor(v));
  // N x N texels from the first; weights 1 - f, 1, ..., 1, f per axis, over (N - 1)^2.
  const double shift = 0.5 + 0.5 * (taps_ - 2);
  const double x0 = std::floor(u - shift), y0 = std::floor(v - shift);
  const double fx = (u - shift) - x0, fy = (v - shift) - y0;
  double sum = 0.0;
  for (int j = 0; j < taps_; ++j) {
    const double wy = j == 0 ? 1.0 - fy : j == taps_ - 1 ? fy : 1.0;
    double row = 0.0;
    for (int i = 0; i < taps_; ++i) {
      const double wx = i == 0 ? 1.0 - fx : i == taps_ - 1 ? fx : 1.0;
      row += wx * lit(x0 + i, y0 + j);
    }
    sum += wy * row;
  }
  const double norm = double(taps_ - 1) * double(taps_ - 1);
  return sum / norm;
}

void ShadowMap::visibility(const LightTarget& t, std::size_t count, const float* px, const float* py, const float* pz,
                           const float* nx, const float* ny, const float* nz, std::size_t stride, float* visible) const {
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t at = i * stride;
    visible[i] = 1.0f;
    if (faces_ == 0 || !may_be_lit(t, px[at], py[at], pz[at], nx[at], ny[at], nz[at])) continue;
    const Eigen::Vector3d p(px[at], py[at], pz[at]);
    Eigen::Vector3d n(nx[at], ny[at], nz[at]);
    Eigen::Vector3d l = t.directional ? Eigen::Vector3d(t.x, t.y, t.z) : Eigen::Vector3d(t.x, t.y, t.z) - p;
    const double n_len = n.norm(), l_len = l.norm();
    if (!(n_len > 0.0) || !(l_len > 0.0) || !p.allFinite() || !std::isfinite(n_len) || !std::isfinite(l_len)) continue;
    n /= n_len, l /= l_len;
    // The face, and the size of one of its texels at the point.
    const Face* f = &face_[0];
    double texel = texel_;
    if (kind_ != Kind::orthographic) {
      if (kind_ == Kind::cube) {  // the major axis of the way from the light, in world space (ties: x, y, z)
        const Eigen::Vector3d d = eye_to_world_.topLeftCorner<3, 3>() * (p - light_eye_);
        const Eigen::Vector3d a = d.cwiseAbs();
        const int axis = a.x() >= a.y() && a.x() >= a.z() ? 0 : a.y() >= a.z() ? 1 : 2;
        f = &face_[2 * axis + (d[axis] < 0.0 ? 1 : 0)];
      }
      const double depth = -(f->from_eye * p.homogeneous()).z();
      texel = 2.0 * std::max(depth, 0.0) * tan_half_ / resolution_;
    }
    // Bias, in filter radii at the point: along the normal, and towards the light (constant, and
    // the slope term: tan of the angle between normal and light, capped). Moved d along its
    // normal, a plane at angle t to the light clears its own depth by d / cos t along the ray,
    // where the filter's taps within r of the point see it at most r tan t nearer: d = r sin t
    // suffices, so d = r clears every angle.
    const double cos_nl = std::clamp(n.dot(l), 0.0, 1.0);
    const double tan_nl = cos_nl > 0.0 ? std::min(std::sqrt(1.0 - cos_nl * cos_nl) / cos_nl, kMaxSlope) : kMaxSlope;
    texel *= reach_;
    const Eigen::Vector3d moved =
        p + texel * (double(bias_.normal) * n + (double(bias_.constant) + double(bias_.slope) * tan_nl) * l);
    const Eigen::Vector3d q = (f->from_eye * moved.homogeneous()).head<3>();
    visible[i] = static_cast<float>(lookup(*f, q));
  }
}

}  // namespace facet::shadow
