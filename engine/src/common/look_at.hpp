// Internal: the look-at (world -> eye) matrix, computed in double. facet::view_matrix rounds it to
// float; the lighting set-up keeps it in double.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "facet/camera.hpp"

namespace facet {

inline Eigen::Matrix4d look_at_d(const Camera& camera) {
  const Eigen::Vector3d eye = camera.eye.cast<double>();
  const Eigen::Vector3d f = (camera.target.cast<double>() - eye).normalized();
  const Eigen::Vector3d s = f.cross(camera.up.cast<double>()).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

}  // namespace facet
