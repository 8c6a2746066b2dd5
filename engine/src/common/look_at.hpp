// Internal: the look-at (world -> eye) matrix, computed in double. facet::view_matrix rounds it to
// float; the lighting set-up keeps it in double.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "facet/camera.hpp"

namespace facet {

// A right-handed view from `eye` looking along unit `forward`, with `up` not parallel to it.
inline Eigen::Matrix4d look_along(const Eigen::Vector3d& eye, const Eigen::Vector3d& forward, const Eigen::Vector3d& up) {
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

// The up vector of a light's view along `forward` (spot shadow maps and projectors share it):
// world +y unless the light is within ~8 degrees of it, then +x. Fixed by the light alone, so the
// view does not turn with the camera.
inline Eigen::Vector3d light_up(const Eigen::Vector3d& forward) {
  return std::abs(forward.y()) < 0.99 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
}

inline Eigen::Matrix4d look_at_d(const Camera& camera) {
  const Eigen::Vector3d eye = camera.eye.cast<double>();
  return look_along(eye, (camera.target.cast<double>() - eye).normalized(), camera.up.cast<double>());
}

}  // namespace facet
