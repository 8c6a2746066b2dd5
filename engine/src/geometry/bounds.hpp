// Internal: a mesh's box, for the frame's culling, ordering and light bounds.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "facet/types.hpp"

namespace facet::geometry {

// Model-space box of the finite vertices among `n` from `p`, or false when there is none.
bool finite_box(const Vec3* p, std::size_t n, Eigen::Vector3d& lo, Eigen::Vector3d& hi);
inline bool finite_box(const std::vector<Vec3>& positions, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  return finite_box(positions.data(), positions.size(), lo, hi);
}

}  // namespace facet::geometry
