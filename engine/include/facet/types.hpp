// Vocabulary types of the scene side (Eigen, array-of-structs, user-facing).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace facet {

using Vec3 = Eigen::Vector3f;
using Color3 = Eigen::Vector3f;  // linear RGB; components may exceed 1 (light intensities)
using Mat4 = Eigen::Matrix4f;

}  // namespace facet
