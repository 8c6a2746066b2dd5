#include "scene/animation.hpp"

#include <algorithm>
#include <cmath>

namespace facet::animation {

namespace {

std::size_t groups_per_key(const Track& t) { return t.interpolation == Interpolation::cubic_spline ? 3 : 1; }

// Key k's value (for cubic_spline the middle of its three groups).
const float* value_of(const Track& t, std::size_t k) {
  const std::size_t c = static_cast<std::size_t>(t.components);
  return t.values.data() + (k * groups_per_key(t) + (groups_per_key(t) == 3 ? 1 : 0)) * c;
}

void normalise4(double* q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (n > 0.0) {
    for (int i = 0; i < 4; ++i) q[i] /= n;
  } else {
    q[0] = q[1] = q[2] = 0.0, q[3] = 1.0;
  }
}

// Spherical linear interpolation from a to b by s on the shortest arc (b negated when the two
// are more than half a turn apart); a straight blend, renormalised, when they nearly coincide.
void slerp(const float* a, const float* b, double s, double* out) {
  double qa[4], qb[4];
  for (int i = 0; i < 4; ++i) qa[i] = a[i], qb[i] = b[i];
  normalise4(qa);
  normalise4(qb);
  double d = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
  if (d < 0.0) {
    for (double& v : qb) v = -v;
    d = -d;
  }
  double wa, wb;
  if (d > 0.9995) {
    wa = 1.0 - s, wb = s;
  } else {
    const double theta0 = std::acos(std::min(d, 1.0)), theta = theta0 * s;
    wb = std::sin(theta) / std::sin(theta0);
    wa = std::cos(theta) - d * wb;
  }
  for (int i = 0; i < 4; ++i) out[i] = wa * qa[i] + wb * qb[i];
  normalise4(out);
}

}  // namespace

Status validate_track(const Track& track, const std::string& where) {
  auto bad = [&](const std::string& field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, where + "." + field, where + "." + field + ": " + what};
  };
  if (track.times.empty()) return bad("input", "no keyframes");
  if (track.times.size() > kMaxKeys) return bad("input", std::to_string(track.times.size()) + " keyframes, at most " + std::to_string(kMaxKeys));
  if (track.components < 1 || track.components > 256 || (track.rotation && track.components != 4)) {
    return bad("output", "expected " + std::string(track.rotation ? "4 components (a quaternion)" : "1 to 256 components") + " per key");
  }
  for (std::size_t k = 0; k < track.times.size(); ++k) {
    const float t = track.times[k];
    if (!std::isfinite(t)) return bad("input", "key " + std::to_string(k) + "'s time is not finite");
    if (k > 0 && !(t > track.times[k - 1])) return bad("input", "key " + std::to_string(k) + "'s time does not follow the one before (times must increase)");
  }
  const std::size_t need = track.times.size() * groups_per_key(track) * static_cast<std::size_t>(track.components);
  if (track.values.size() != need) {
    return bad("output", std::to_string(track.values.size()) + " values for " + std::to_string(track.times.size()) +
                             " keys, expected " + std::to_string(need));
  }
  for (std::size_t i = 0; i < track.values.size(); ++i) {
    if (!std::isfinite(track.values[i])) return bad("output", "value " + std::to_string(i) + " is not finite");
  }
  return {};
}

void sample(const Track& track, double t, float* out) {
  const std::size_t c = static_cast<std::size_t>(track.components), keys = track.times.size();
  auto copy = [&](const float* v) {
    double q[4];
    if (track.rotation) {
      for (int i = 0; i < 4; ++i) q[i] = v[i];
      normalise4(q);
      for (int i = 0; i < 4; ++i) out[i] = static_cast<float>(q[i]);
      return;
    }
    std::copy(v, v + c, out);
  };
  if (!(t > double(track.times.front())) || keys == 1) return copy(value_of(track, 0));  // before the first key (NaN too)
  if (t >= double(track.times.back())) return copy(value_of(track, keys - 1));
  // The keys around t: k with times[k] <= t < times[k + 1].
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(track.times.begin(), track.times.end(), t) - track.times.begin()) - 1;
  const double t0 = track.times[k], t1 = track.times[k + 1], interval = t1 - t0, s = (t - t0) / interval;
  const float* a = value_of(track, k);
  const float* b = value_of(track, k + 1);
  switch (track.interpolation) {
    case Interpolation::step: return copy(a);
    case Interpolation::linear:
      if (track.rotation) {
        double q[4];
        slerp(a, b, s, q);
        for (int i = 0; i < 4; ++i) out[i] = static_cast<float>(q[i]);
        return;
      }
      for (std::size_t i = 0; i < c; ++i) out[i] = static_cast<float>(double(a[i]) + (double(b[i]) - double(a[i])) * s);
      return;
    case Interpolation::cubic_spline: {
      // Hermite: p = (2s^3 - 3s^2 + 1) v_k + d (s^3 - 2s^2 + s) out_k + (3s^2 - 2s^3) v_k+1 + d (s^3 - s^2) in_k+1.
      const float* out_tangent = a + c;    // key k's third group
      const float* in_tangent = b - c;     // key k + 1's first group
      const double s2 = s * s, s3 = s2 * s;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = 3 * s2 - 2 * s3, h11 = s3 - s2;
      double v[256];
      for (std::size_t i = 0; i < c; ++i) {
        v[i] = h00 * a[i] + interval * h10 * out_tangent[i] + h01 * b[i] + interval * h11 * in_tangent[i];
      }
      if (track.rotation) normalise4(v);
      for (std::size_t i = 0; i < c; ++i) out[i] = static_cast<float>(v[i]);
      return;
    }
  }
}

}  // namespace facet::animation
